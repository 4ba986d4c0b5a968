//! `grove trees`: parametric trees after Weber and Penn from species presets (`docs/species.md`);
//! parses the arguments and calls `grove::species`.

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use clap::{Args, Subcommand};

/// Subcommands of `grove trees`.
#[derive(Subcommand)]
pub enum TreesCommand {
    /// Generate a species' tree as glTF (full, about 25 % and 5 % of the triangles) with its textures.
    Generate(GenerateArgs),
    /// List the shipped species presets.
    List,
}

/// Arguments of `grove trees generate`.
#[derive(Args)]
pub struct GenerateArgs {
    /// A preset in assets/species (oak, birch, beech, scots_pine, norway_spruce, shrub) or the path of a .ron file.
    #[arg(long)]
    pub species: String,
    /// The seed: the same species and seed give the same bytes.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// The output folder (created if missing; existing files are never replaced).
    #[arg(long)]
    pub out: PathBuf,
}

/// Runs a `grove trees` subcommand.
pub fn run(cmd: TreesCommand) -> anyhow::Result<ExitCode> {
    match cmd {
        TreesCommand::List => {
            for n in grove::species::preset::preset_names() {
                println!("{n}");
            }
        }
        TreesCommand::Generate(a) => {
            let t0 = Instant::now();
            let w = grove::species::output::write(&a.species, a.seed, &a.out)?;
            let m = &w.model;
            let (lo, hi) = m.bounds();
            println!(
                "{}: {} stems, {} leaves, {} triangles (lod1 {}, lod2 {}), {:.1} m tall, crown radius {:.1} m, {:.2} s",
                w.gltf.display(),
                m.tree.stems.len(),
                m.lods[0].leaf_count,
                m.lods[0].triangles(),
                m.lods[1].triangles(),
                m.lods[2].triangles(),
                hi.y - lo.y.min(0.0),
                m.crown_radius(),
                t0.elapsed().as_secs_f64()
            );
        }
    }
    Ok(ExitCode::SUCCESS)
}
