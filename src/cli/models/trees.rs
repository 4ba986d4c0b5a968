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
    /// Also add one level of detail of the written model to a model bank (`grove models add`;
    /// docs/model-bank.md), as species NAME: the folder --bank, or the first GROVE_BANK folder.
    #[arg(long)]
    pub add: bool,
    /// The bank folder for --add.
    #[arg(long, requires = "add")]
    pub bank: Option<PathBuf>,
    /// The level of detail --add adds: 0 every triangle, 1 about 25 %, 2 about 5 %.
    #[arg(long, requires = "add", default_value_t = 0, value_parser = clap::value_parser!(u8).range(0..=2))]
    pub lod: u8,
    /// The model's name in the bank (default: the species' name, with `-lod1` or `-lod2` for --lod 1 or 2).
    #[arg(long, requires = "add")]
    pub name: Option<String>,
    /// The model's kind in the bank's menu (default: measured from the leaves' cards).
    #[arg(long, value_enum, requires = "add")]
    pub kind: Option<super::KindArg>,
    /// A coarser model of the same tree already in the bank (say its `--lod 2`), drawn in this
    /// one's place where the tree is small on screen (docs/model-bank.md, "Far models").
    #[arg(long, value_name = "NAME", requires = "add")]
    pub far: Option<String>,
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
            let bank = if a.add { Some(super::bank_for_add(a.bank.clone())?) } else { None };
            if let Some(name) = &a.name {
                super::check_model_name(name)?;
            }
            let w = grove::species::output::write(&a.species, a.seed, &a.out)?;
            let m = &w.model;
            let (lo, hi) = m.bounds();
            let (card, spray) = (&m.atlas.card, &m.atlas.sprays[0]);
            println!(
                "{}: {} stems, {} leaf cards of {} leaves ({:.0} cm), sprays of {} ({:.0} cm) on the coarser levels, {} triangles (lod1 {}, lod2 {}), {:.1} m tall, crown radius {:.1} m, {:.2} s",
                w.gltf.display(),
                m.tree.stems.len(),
                m.tree.leaves.len(),
                card.leaves,
                card.size.x * 100.0,
                spray.leaves,
                spray.size.x * 100.0,
                m.lods[0].triangles(),
                m.lods[1].triangles(),
                m.lods[2].triangles(),
                hi.y - lo.y.min(0.0),
                m.crown_radius(),
                t0.elapsed().as_secs_f64()
            );
            if let Some(bank) = bank {
                let lod = usize::from(a.lod);
                let name = a.name.clone().unwrap_or_else(|| grove::species::output::lod_name(&m.name, lod));
                let req = grove::bank::import::AddRequest {
                    file: a.out.join(format!("{}.gltf", grove::species::output::lod_name(&m.name, lod))),
                    bank: bank.clone(),
                    name: Some(name),
                    species: Some(m.name.clone()),
                    kind: a.kind.map(super::KindArg::kind),
                    far: a.far.clone(),
                };
                super::print_added(&grove::bank::import::add(&req)?, &bank);
            }
        }
    }
    Ok(ExitCode::SUCCESS)
}
