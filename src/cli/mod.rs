//! Subcommands of the `grove` tool, one module each, and the helpers they share.

pub mod aerial;
pub mod aerial_layers;
pub mod aerial_bench;
pub mod aerial_flight;
pub mod aerial_tile;
pub mod assets;
pub mod bench;
pub mod bench_grass;
pub mod bench_impostor;
pub mod bench_park;
pub mod bench_raycast;
pub mod bench_render;
pub mod bench_replay;
pub mod bench_water;
pub mod bench_wind;
pub mod lsystem;
pub mod models;
pub mod play;
pub mod render;
pub mod replay;
pub mod replay_seal;
pub mod replay_upgrade;
pub mod scene;
pub mod sim;
pub mod study;
pub mod study_merge;
pub mod study_report;
pub mod sun;
pub mod synth;
pub mod view;

use std::path::Path;

use grove_systems::scene::Scene;

/// Formats an error and its causes as a single line.
pub fn one_line(e: &anyhow::Error) -> String {
    format!("{e:#}").replace('\n', " ")
}

/// Replaces the default panic message (and backtrace) with one line. A panic is a bug in
/// grove; this keeps even that case to a single, clear line on stderr.
pub fn install_panic_hook() {
    std::panic::set_hook(Box::new(|info| {
        let msg = info
            .payload()
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| info.payload().downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "unknown cause".into());
        let at = info.location().map(|l| format!(" at {}:{}", l.file(), l.line())).unwrap_or_default();
        eprintln!("error: internal error{at}: {}; please report this", msg.replace('\n', " "));
    }));
}

/// Loads a scene file, with the error naming the file.
pub fn load_scene(path: &Path) -> anyhow::Result<Scene> {
    Ok(Scene::load(path)?)
}

/// Prints a value as pretty JSON on stdout.
pub fn print_json<T: serde::Serialize>(value: &T) -> anyhow::Result<()> {
    println!("{}", serde_json::to_string_pretty(value)?);
    Ok(())
}
