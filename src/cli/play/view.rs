//! `grove view FILE`: a replay viewer in a window.
//!
//! An unreadable or malformed file is a one-line error with exit code 2; a divergent or
//! incomplete one opens with a banner.

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::anyhow;
use clap::Args;

use crate::desktop::viewer::{ViewApp, Viewer};

/// Arguments of `grove view`.
#[derive(Args)]
pub struct ViewArgs {
    /// The recording (JSON Lines, see docs/replay-format.md).
    pub file: PathBuf,
    /// Open at this tick.
    #[arg(long)]
    pub at: Option<u64>,
    /// Start playing at once.
    #[arg(long)]
    pub play: bool,
    /// Draw a simple painted view instead of the wgpu renderer (faster on software GPUs).
    #[arg(long)]
    pub simple_view: bool,
}

/// Runs `grove view`.
pub fn run(args: ViewArgs) -> anyhow::Result<ExitCode> {
    let mut viewer = match Viewer::open(&args.file) {
        Ok(v) => v,
        Err(e) => {
            eprintln!("error: {}", e.to_string().replace('\n', " "));
            return Ok(ExitCode::from(2));
        }
    };
    if let Some(b) = &viewer.banner {
        eprintln!("warning: {}: {b}", args.file.display());
    }
    if let Some(t) = args.at {
        viewer.seek(t);
    }
    viewer.playing = args.play;
    let mut app = ViewApp::new(viewer);
    if !args.simple_view {
        app.world3d.factory = Some(crate::desktop::gpu::make_renderer);
    }
    crate::desktop::window::run("grove view", app).map_err(|e| anyhow!(e))?;
    Ok(ExitCode::SUCCESS)
}
