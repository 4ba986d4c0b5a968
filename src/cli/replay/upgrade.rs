//! `grove replay --upgrade IN --out OUT`: rewrite a version-1 recording as version 2 (the same
//! events and checkpoints, with chained checksums; see docs/replay-format.md).
//!
//! Every line is checked as the replay checks it, so a corrupt file is refused with one line
//! (exit 2) and nothing is written. The output goes through a temporary file and a rename; an
//! existing OUT is refused without `--force`.

use std::path::Path;
use std::process::ExitCode;

use anyhow::{anyhow, bail};
use grove::atomic_write::write_via_temp;
use grove_systems::replay::{UpgradeSummary, upgrade};

/// Runs the upgrade of `input` into `out`.
pub fn run(input: &Path, out: Option<&Path>, force: bool) -> anyhow::Result<ExitCode> {
    let out = out.ok_or_else(|| anyhow!("--upgrade needs --out FILE for the version-2 recording"))?;
    if input.is_dir() {
        bail!("{}: is a directory, not a recording", input.display());
    }
    if out.is_dir() {
        bail!("{}: is a directory; --out needs a file name", out.display());
    }
    if out.exists() && !force {
        bail!("{}: already exists (use --force to overwrite)", out.display());
    }
    if let (Ok(a), Ok(b)) = (input.canonicalize(), out.canonicalize())
        && a == b
    {
        bail!("{}: --out is the input file; write the upgrade to another file", out.display());
    }
    if let Some(parent) = out.parent()
        && !parent.as_os_str().is_empty()
        && !parent.is_dir()
    {
        bail!("{}: folder does not exist", parent.display());
    }
    let file = input.display().to_string();
    let (f, _) = grove_systems::files::open(input, grove_systems::files::Kind::Recording)?;
    let summary: UpgradeSummary = write_via_temp(out, |tmp| {
        let w = std::fs::File::create(tmp).map_err(|e| anyhow!("{}: cannot write ({e})", out.display()))?;
        let mut w = std::io::BufWriter::new(w);
        let summary = upgrade(f, &file, &mut w).map_err(|e| anyhow!("{e}"))?;
        w.into_inner().map_err(|e| anyhow!("{}: cannot write ({e})", out.display()))?.sync_all()?;
        Ok(summary)
    })?;
    println!(
        "{}: wrote {} lines in format version 2 from {}{}{}",
        out.display(),
        summary.lines,
        file,
        if summary.complete { "" } else { " (the input has no footer: incomplete)" },
        if summary.cut { "; its cut last line was left out" } else { "" }
    );
    Ok(ExitCode::SUCCESS)
}
