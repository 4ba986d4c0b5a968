//! `grove assets`: regenerate the tree models, textures, catalogue and environment maps.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Args;

/// Arguments of `grove assets`.
#[derive(Args)]
pub struct AssetsArgs {
    /// The output folder; models go to OUT/trees, the sky and ground to OUT/env.
    #[arg(long, default_value = "assets")]
    pub out: PathBuf,
}

/// Runs `grove assets`.
pub fn run(args: AssetsArgs) -> anyhow::Result<ExitCode> {
    let summary = grove::assetgen::generate(&args.out)?;
    for m in &summary.catalogue.models {
        println!(
            "{:<20} {:>5} triangles, height {:.2} m, crown radius {:.2} m",
            m.name,
            m.triangles,
            m.height(),
            m.crown_radius
        );
    }
    println!("{}: wrote {} files", args.out.display(), summary.files);
    Ok(ExitCode::SUCCESS)
}
