//! `grove models`: the model bank (docs/model-bank.md).
//!
//! - `grove models add FILE --bank DIR [--name N] [--species S] [--kind mesh|billboard]`
//! - `grove models list [--bank DIR]... [--json]`
//! - `grove models check [--bank DIR]...`
//!
//! Banks are the `--bank` folders in order, then those of `GROVE_BANK` (colon-separated); the
//! shipped models (`assets/trees`) always come first.

pub mod assets;
pub mod lsystem;
pub mod trees;

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::anyhow;
use clap::{Args, Subcommand, ValueEnum};
use grove::bank::import::{AddRequest, Added, add_noted, load_checked};
use grove::models::measure;
use grove_systems::bank::{Bank, BankModel};
use grove_systems::catalogue::{Catalogue, ModelKind, PICK_BANDS, PickShape};
use serde::Serialize;

/// The kinds a user can name.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum KindArg {
    /// Foliage as geometry.
    Mesh,
    /// Foliage as alpha-clipped cards.
    Billboard,
}

impl KindArg {
    /// The catalogue's kind.
    pub fn kind(self) -> ModelKind {
        match self {
            KindArg::Mesh => ModelKind::Mesh,
            KindArg::Billboard => ModelKind::Billboard,
        }
    }
}

/// The bank folder a generator's `--add` writes to: `--bank`, or the first GROVE_BANK folder.
pub fn bank_for_add(bank: Option<PathBuf>) -> anyhow::Result<PathBuf> {
    match bank {
        Some(b) => Ok(b),
        None => grove::bank::session_dirs(&[])
            .into_iter()
            .next()
            .ok_or_else(|| anyhow!("--add needs --bank DIR (or GROVE_BANK)")),
    }
}

/// Refuses a model name a bank cannot hold, with one line (before anything is generated).
pub fn check_model_name(name: &str) -> anyhow::Result<()> {
    if !grove_systems::bank::valid_name(name) || name.contains('.') {
        let shown: String = name.chars().take(40).collect();
        anyhow::bail!(
            "model name '{shown}{}' must be 1 to 64 letters, digits, '-' and '_'",
            if name.chars().count() > 40 { "…" } else { "" }
        );
    }
    Ok(())
}

/// One line saying what a generator's `--add` did.
pub fn print_added(added: &Added, bank: &std::path::Path) {
    match added {
        Added::New(m) => println!(
            "added '{}' to {} (lowest point {:.3} m, {} triangles)",
            m.name,
            bank.display(),
            m.bounds_min.y,
            m.triangles
        ),
        Added::Unchanged(m) => println!("'{}' is already in {} with the same files", m.name, bank.display()),
    }
}

/// `grove models` subcommands.
#[derive(Subcommand)]
pub enum ModelsCommand {
    /// Validate a glTF model, measure it and copy it (with its buffers and textures) into a bank.
    Add(AddArgs),
    /// List the shipped models and those of every bank.
    List(ListArgs),
    /// Check that every catalogue entry still matches its files (exit 1 if one does not).
    Check(ListArgs),
}

/// Arguments of `grove models add`.
#[derive(Args)]
pub struct AddArgs {
    /// The glTF 2.0 file (.gltf with its buffers and textures, or .glb).
    pub file: PathBuf,
    /// The bank folder to add it to (created when missing); default: the first GROVE_BANK folder.
    #[arg(long)]
    pub bank: Option<PathBuf>,
    /// The model's name (default: the file's stem); 1 to 64 letters, digits, '-', '_' or '.'.
    #[arg(long)]
    pub name: Option<String>,
    /// The species (default: the name).
    #[arg(long)]
    pub species: Option<String>,
    /// The kind (default: billboard when most triangles use alpha-clipped materials, else mesh).
    #[arg(long, value_enum)]
    pub kind: Option<KindArg>,
    /// A coarser model of the same tree, already in the bank, drawn in this one's place where
    /// the tree is small on screen (docs/model-bank.md, "Far models").
    #[arg(long, value_name = "NAME")]
    pub far: Option<String>,
}

/// Arguments of `grove models list` and `grove models check`.
#[derive(Args)]
pub struct ListArgs {
    /// A bank folder (repeatable), searched after the shipped models and before GROVE_BANK's.
    #[arg(long = "bank", value_name = "DIR")]
    pub banks: Vec<PathBuf>,
    /// Print JSON instead of text.
    #[arg(long)]
    pub json: bool,
}

/// One model as `grove models list --json` prints it.
#[derive(Serialize)]
pub struct Listed {
    /// The model's id in a session with these banks.
    pub id: u8,
    /// Its name.
    pub name: String,
    /// Its species.
    pub species: String,
    /// "mesh" or "billboard".
    pub kind: &'static str,
    /// "shipped" or the bank folder.
    pub bank: String,
    /// The glTF file.
    pub file: String,
    /// Height from the lowest point to the top, metres.
    pub height: f32,
    /// The lowest point, metres (model space).
    pub lowest_point: f32,
    /// Triangles.
    pub triangles: u32,
    /// Content hash (bank models only).
    pub hash: Option<String>,
    /// Thumbnail PNG (bank models only).
    pub thumbnail: Option<String>,
}

fn kind_name(k: ModelKind) -> &'static str {
    match k {
        ModelKind::Mesh => "mesh",
        ModelKind::Billboard => "billboard",
    }
}

/// Runs `grove models`.
pub fn run(cmd: ModelsCommand) -> anyhow::Result<ExitCode> {
    match cmd {
        ModelsCommand::Add(a) => run_add(a),
        ModelsCommand::List(a) => run_list(a),
        ModelsCommand::Check(a) => run_check(a),
    }
}

fn run_add(a: AddArgs) -> anyhow::Result<ExitCode> {
    let bank = match a.bank {
        Some(b) => b,
        None => grove::bank::session_dirs(&[])
            .into_iter()
            .next()
            .ok_or_else(|| anyhow!("name the bank folder with --bank DIR (or set GROVE_BANK)"))?,
    };
    let kind = a.kind.map(KindArg::kind);
    let req = AddRequest { file: a.file, bank: bank.clone(), name: a.name, species: a.species, kind, far: a.far };
    let (added, data) = add_noted(&req)?;
    for w in &data.warnings {
        eprintln!("warning: {w}");
    }
    let notes: String = data.notes.iter().map(|n| format!("; {n}")).collect();
    match added {
        Added::New(m) => println!(
            "added '{}' ({}, {}) to {}: {:.2} m tall, lowest point {:.3} m, {} triangles, wind {}{notes}",
            m.name,
            m.species,
            kind_name(m.kind),
            bank.display(),
            m.bounds_max.y - m.bounds_min.y,
            m.bounds_min.y,
            m.triangles,
            match m.wind {
                grove_systems::bank::WindSource::Own => "from the file",
                grove_systems::bank::WindSource::Computed => "computed",
            }
        ),
        Added::Unchanged(m) => {
            println!("'{}' is already in {} with the same files; nothing changed", m.name, bank.display())
        }
    }
    Ok(ExitCode::SUCCESS)
}

fn listed(banks: &[PathBuf]) -> anyhow::Result<Vec<Listed>> {
    let banks = grove::bank::open_session(banks).map_err(|e| anyhow!(e))?;
    let (cat, _) = banks.session_catalogue().map_err(|e| anyhow!(e))?;
    let shipped = grove::bank::shipped_dir();
    let mut out = Vec::new();
    for m in &cat.models {
        let bank_model = banks.find(&m.name);
        out.push(Listed {
            id: m.id.0,
            name: m.name.clone(),
            species: m.species.clone(),
            kind: kind_name(m.kind),
            bank: bank_model.map_or("shipped".into(), |(b, _)| b.dir.display().to_string()),
            file: bank_model.map_or_else(
                || shipped.join(format!("{}.gltf", m.name)).display().to_string(),
                |(b, bm)| b.file_of(bm).display().to_string(),
            ),
            height: m.height(),
            lowest_point: m.lowest_point(),
            triangles: m.triangles,
            hash: bank_model.map(|(_, bm)| bm.hash.clone()),
            thumbnail: bank_model
                .and_then(|(b, bm)| bm.thumbnail.as_ref().map(|t| b.dir.join(t).display().to_string())),
        });
    }
    Ok(out)
}

fn run_list(a: ListArgs) -> anyhow::Result<ExitCode> {
    let all = listed(&a.banks)?;
    if a.json {
        crate::cli::print_json(&all)?;
    } else {
        for m in &all {
            println!(
                "{:>3}  {:<24} {:<12} {:<9} {:>6.2} m {:>7} tris  {}",
                m.id, m.name, m.species, m.kind, m.height, m.triangles, m.bank
            );
        }
    }
    Ok(ExitCode::SUCCESS)
}

/// Differences between catalogue measurements and a fresh measurement, as short phrases.
fn differences(
    bmin: glam::Vec3,
    bmax: glam::Vec3,
    tris: u32,
    pick: Option<&PickShape>,
    m: &grove::models::Measured,
) -> Vec<String> {
    let mut out = Vec::new();
    let tol = 1e-3 * (1.0 + (bmax - bmin).max_element());
    if (bmin - m.bounds_min).abs().max_element() > tol || (bmax - m.bounds_max).abs().max_element() > tol {
        out.push(format!(
            "bounds are {:?}..{:?} in the file, {:?}..{:?} in the catalogue",
            m.bounds_min.to_array(),
            m.bounds_max.to_array(),
            bmin.to_array(),
            bmax.to_array()
        ));
    }
    if tris != m.triangles {
        out.push(format!("{} triangles in the file, {tris} in the catalogue", m.triangles));
    }
    if let Some(p) = pick {
        let off = (0..PICK_BANDS).any(|i| (p.radii[i] - m.pick.radii[i]).abs() > tol)
            || (p.top - m.pick.top).abs() > tol
            || (p.bottom - m.pick.bottom).abs() > tol;
        if off {
            out.push("the pick shape differs".into());
        }
    }
    out
}

fn check_bank_model(bank: &Bank, m: &BankModel) -> Vec<String> {
    let mut out = Vec::new();
    match bank.current_hash(m) {
        Ok(h) if h == m.hash => {}
        Ok(h) => out.push(format!("its files hash to {h}, the catalogue has {}", m.hash)),
        Err(e) => return vec![e.to_string()],
    }
    match load_checked(&bank.file_of(m)) {
        Ok(data) => out.extend(differences(m.bounds_min, m.bounds_max, m.triangles, Some(&m.pick), &measure(&data))),
        Err(e) => out.push(crate::cli::one_line(&e.into())),
    }
    out
}

fn run_check(a: ListArgs) -> anyhow::Result<ExitCode> {
    let banks = grove::bank::open_session(&a.banks).map_err(|e| anyhow!(e))?;
    banks.models().map_err(|e| anyhow!(e))?;
    let shipped = grove::bank::shipped_dir();
    let mut report: Vec<(String, String, Vec<String>)> = Vec::new();
    for m in &Catalogue::builtin().models {
        let file = shipped.join(format!("{}.gltf", m.name));
        let problems = match load_checked(&file) {
            Ok(data) => differences(m.bounds_min, m.bounds_max, m.triangles, m.pick.as_ref(), &measure(&data)),
            Err(e) => vec![crate::cli::one_line(&e.into())],
        };
        report.push((m.name.clone(), "shipped".into(), problems));
    }
    for b in &banks.banks {
        for m in &b.catalogue.models {
            report.push((m.name.clone(), b.dir.display().to_string(), check_bank_model(b, m)));
        }
    }
    let bad = report.iter().filter(|r| !r.2.is_empty()).count();
    if a.json {
        let v: Vec<serde_json::Value> = report
            .iter()
            .map(|(n, b, p)| serde_json::json!({ "name": n, "bank": b, "ok": p.is_empty(), "problems": p }))
            .collect();
        crate::cli::print_json(&serde_json::json!({ "models": v, "mismatched": bad }))?;
    } else {
        for (n, b, p) in &report {
            if p.is_empty() {
                println!("ok        {n} ({b})");
            } else {
                println!("CHANGED   {n} ({b}): {}", p.join("; "));
            }
        }
        println!("{} models, {bad} do not match their files", report.len());
    }
    Ok(if bad == 0 { ExitCode::SUCCESS } else { ExitCode::from(1) })
}
