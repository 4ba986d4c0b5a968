//! `grove replay --seal IN --out OUT`: turn an event-only recording (for example events
//! converted from another tool) into a verifiable one.
//!
//! The input is read and re-simulated like any replay, so every rule of `docs/replay-format.md`
//! applies and bad input is exit 2. Its input events are then re-simulated once more from a
//! fresh simulation and written with a checkpoint every 60 ticks and a footer
//! (`grove_systems::replay::record_events`). Event lines keep their ticks; their `ms` and
//! `frame` fields are rewritten from the tick. The output is written to a temporary file and
//! renamed, and an existing file is never overwritten.

use std::path::Path;
use std::process::ExitCode;

use anyhow::{anyhow, bail};
use grove_systems::bank::Banks;
use grove_systems::replay::{ReplayOptions, read_events, record_events_beside, replay_file};

/// Seals `input` into `out`. Returns exit code 1 when `input` has checkpoints that diverge
/// (sealing would hide that); errors are bad input (exit 2).
pub fn run(input: &Path, out: Option<&Path>) -> anyhow::Result<ExitCode> {
    let out = out.ok_or_else(|| anyhow!("--seal needs --out OUT"))?;
    if out.exists() {
        bail!("{}: already exists; grove never overwrites a recording (choose another --out)", out.display());
    }
    if out.parent().is_some_and(|p| !p.as_os_str().is_empty() && !p.is_dir()) {
        bail!("{}: the folder does not exist", out.display());
    }
    // First the ordinary replay: it validates every line, event and name.
    let outcome = replay_file(input, &ReplayOptions::default()).map_err(|e| anyhow!("{e}"))?;
    if let Some(d) = &outcome.first_divergence {
        eprintln!(
            "error: {}: diverges from its own checkpoints at tick {}; sealing would replace them, so it is refused",
            input.display(),
            d.tick
        );
        return Ok(ExitCode::from(1));
    }
    let end_tick = outcome.sim.tick();
    let (header, events) = read_events(input).map_err(|e| anyhow!("{e}"))?;
    let summary = serde_json::json!({ "generator": "grove replay --seal" });
    let tmp = out.with_extension("seal.tmp");
    let written = (|| -> anyhow::Result<()> {
        let file = std::fs::File::create(&tmp).map_err(|e| anyhow!("{}: {e}", tmp.display()))?;
        let w = record_events_beside(
            std::io::BufWriter::new(file),
            &header,
            &events,
            end_tick,
            summary,
            input.parent(),
            &Banks::default(),
        )
        .map_err(|e| anyhow!("{}: {e}", input.display()))?;
        w.into_inner().map_err(|e| anyhow!("{}: {}", tmp.display(), e.error()))?.sync_all()?;
        std::fs::rename(&tmp, out).map_err(|e| anyhow!("{}: {e}", out.display()))?;
        Ok(())
    })();
    if let Err(e) = written {
        let _ = std::fs::remove_file(&tmp);
        return Err(e);
    }
    // Check what was written, the way any reader will.
    let sealed = replay_file(out, &ReplayOptions::default()).map_err(|e| anyhow!("{e}"))?;
    println!(
        "sealed {} into {}: {} events, {} checkpoints verified, final tick {}",
        input.display(),
        out.display(),
        events.len(),
        sealed.checkpoints_checked,
        sealed.sim.tick()
    );
    Ok(ExitCode::SUCCESS)
}
