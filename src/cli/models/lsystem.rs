//! `grove lsystem`: derive L-systems (CPU or GPU), write them as glTF tree models, and benchmark
//! derivation and interpretation. See `docs/lsystem.md`.

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use anyhow::bail;
use clap::{Args, Subcommand};
use grove::lsystem::gpu::GpuDeriver;
use grove::lsystem::grammar::{COMMANDS, Source};
use grove::lsystem::{Grammar, LString, Limits, derive, memo, mesh, presets, turtle};
use indicatif::{ProgressBar, ProgressStyle};

/// Subcommands of `grove lsystem`.
#[derive(Subcommand)]
pub enum LsystemCommand {
    /// Derive a grammar n times and print the length and the count of each symbol.
    Derive(DeriveArgs),
    /// Derive a grammar and write it as a glTF tree model (tubes and leaf cards, with wind channels).
    Model(ModelArgs),
    /// Time derivation (CPU 1 and 2 threads, GPU compute) and interpretation of a preset for several n.
    Bench(BenchArgs),
}

/// Where the grammar comes from.
#[derive(Args, Clone)]
pub struct GrammarArgs {
    /// A built-in grammar: bush1..3, abop-a..f (ABOP Fig. 1.24), broadleaf, conifer, birch, shrub.
    #[arg(long, conflicts_with_all = ["grammar", "axiom"])]
    pub preset: Option<String>,
    /// A grammar file (format in docs/lsystem.md).
    #[arg(long, conflicts_with = "axiom")]
    pub grammar: Option<PathBuf>,
    /// An axiom given on the command line (with --rule and --angle).
    #[arg(long)]
    pub axiom: Option<String>,
    /// A rule, e.g. 'X=F[+X]F' or 'F(l) -> F(l*0.8)[+F(l*0.6)]' (repeatable; with --axiom).
    #[arg(long = "rule", requires = "axiom")]
    pub rules: Vec<String>,
    /// The turning angle in degrees (with --axiom; default 25).
    #[arg(long, requires = "axiom", allow_negative_numbers = true)]
    pub angle: Option<f32>,
    /// Derivation count (default: the grammar's `n`).
    #[arg(long)]
    pub n: Option<u32>,
    /// Seed of the stochastic rules.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Stop when a derived string would have more symbols than this.
    #[arg(long, default_value_t = 1 << 30)]
    pub max_symbols: u64,
    /// Stop when a derived string (symbols and parameters) or the segments would need more bytes than this.
    #[arg(long, default_value_t = 2 << 30)]
    pub max_bytes: u64,
}

/// The most derivation steps a command accepts.
const MAX_N: u32 = 1000;

impl GrammarArgs {
    fn grammar(&self) -> anyhow::Result<Grammar> {
        let g = self.grammar_unchecked()?;
        if self.n.unwrap_or(g.n) > MAX_N {
            bail!("--n {} is more than {MAX_N} derivation steps", self.n.unwrap_or(g.n));
        }
        Ok(g)
    }

    fn grammar_unchecked(&self) -> anyhow::Result<Grammar> {
        if let Some(p) = &self.preset {
            return Ok(presets::preset(p)?);
        }
        if let Some(path) = &self.grammar {
            let text = grove_systems::files::read_text(path, grove_systems::files::Kind::Grammar)?;
            return Ok(Grammar::parse_file(&text, &path.display().to_string())?);
        }
        if let Some(axiom) = &self.axiom {
            let src = Source {
                axiom: axiom.clone(),
                rules: self.rules.clone(),
                angle_deg: self.angle.unwrap_or(25.0),
                ..Source::default()
            };
            return Ok(Grammar::compile(&src)?);
        }
        bail!("give a grammar: --preset NAME, --grammar FILE or --axiom A --rule 'X=...'");
    }

    fn limits(&self) -> Limits {
        Limits { max_symbols: self.max_symbols, max_bytes: self.max_bytes }
    }
}

/// Arguments of `grove lsystem derive`.
#[derive(Args)]
pub struct DeriveArgs {
    #[command(flatten)]
    pub src: GrammarArgs,
    /// Derive with a wgpu compute pass (lavapipe when there is no GPU).
    #[arg(long)]
    pub gpu: bool,
    /// Threads of the CPU derivation (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
    /// Print JSON: {"length": …, "counts": {"F": …}, "hash": …}.
    #[arg(long)]
    pub json: bool,
    /// Also print the derived string (at most 1,000,000 symbols).
    #[arg(long)]
    pub print: bool,
}

/// Arguments of `grove lsystem model`.
#[derive(Args)]
pub struct ModelArgs {
    #[command(flatten)]
    pub src: GrammarArgs,
    /// The output folder: NAME.gltf, NAME.bin and textures/.
    #[arg(long)]
    pub out: PathBuf,
    /// The model's file name (default: the grammar's name).
    #[arg(long)]
    pub name: Option<String>,
    /// The model's height, metres (default: the grammar's `height`, 6 m unless it says otherwise).
    #[arg(long)]
    pub height: Option<f32>,
    /// Also add the written model to a model bank (`grove models add`; docs/model-bank.md), as
    /// species "lsystem-GRAMMAR": the folder --bank, or the first GROVE_BANK folder.
    #[arg(long)]
    pub add: bool,
    /// The bank folder for --add.
    #[arg(long, requires = "add")]
    pub bank: Option<PathBuf>,
}

/// Arguments of `grove lsystem bench`.
#[derive(Args)]
pub struct BenchArgs {
    /// The preset to time.
    #[arg(long, default_value = "bush2")]
    pub preset: String,
    /// Derivation counts, comma-separated.
    #[arg(long, value_delimiter = ',', default_value = "5,6,7,8")]
    pub n: Vec<u32>,
    /// Runs per measurement (the fastest is reported).
    #[arg(long, default_value_t = 3)]
    pub repeats: u32,
    /// Skip the GPU derivation.
    #[arg(long)]
    pub no_gpu: bool,
    /// Print JSON instead of a Markdown table.
    #[arg(long)]
    pub json: bool,
}

/// Runs `grove lsystem`.
pub fn run(cmd: LsystemCommand) -> anyhow::Result<ExitCode> {
    match cmd {
        LsystemCommand::Derive(a) => run_derive(a),
        LsystemCommand::Model(a) => run_model(a),
        LsystemCommand::Bench(a) => run_bench(a),
    }
}

fn cpu_derive(g: &Grammar, n: u32, seed: u64, limits: &Limits, threads: Option<usize>) -> anyhow::Result<LString> {
    let bar = ProgressBar::new(n as u64)
        .with_style(ProgressStyle::with_template("{msg} {bar:30} {pos}/{len} steps").expect("valid template"));
    bar.set_message(format!("deriving {}", g.name));
    let work = || -> anyhow::Result<LString> {
        let mut s = derive::axiom(g);
        for k in 1..=n {
            s = derive::step(g, &s, k, seed, limits)?;
            bar.inc(1);
        }
        Ok(s)
    };
    let r = match threads {
        Some(t) => rayon::ThreadPoolBuilder::new().num_threads(t.max(1)).build()?.install(work),
        None => work(),
    };
    bar.finish_and_clear();
    r
}

fn run_derive(a: DeriveArgs) -> anyhow::Result<ExitCode> {
    let g = a.src.grammar()?;
    let n = a.src.n.unwrap_or(g.n);
    let limits = a.src.limits();
    if a.threads == Some(0) {
        bail!("--threads must be at least 1");
    }
    let s = if a.gpu {
        GpuDeriver::new()?.derive(&g, n, a.src.seed, &limits)?
    } else {
        cpu_derive(&g, n, a.src.seed, &limits, a.threads)?
    };
    if a.print && s.len() > 1_000_000 {
        bail!("the derived string has {} symbols, too many to print (at most 1,000,000)", s.len());
    }
    let counts = s.counts();
    let mut map = serde_json::Map::new();
    for c in (b'A'..=b'Z').chain(b'a'..=b'z').chain(COMMANDS.iter().copied()) {
        if counts[c as usize] > 0 {
            map.insert((c as char).to_string(), counts[c as usize].into());
        }
    }
    if a.json {
        let mut v = serde_json::json!({"length": s.len(), "counts": map, "hash": format!("{:016x}", s.hash())});
        if a.print {
            v["string"] = s.to_text(&g).into();
        }
        println!("{v}");
    } else {
        println!("{}: n = {n}, length {}, hash {:016x}", g.name, s.len(), s.hash());
        for (k, v) in &map {
            println!("  {k} {v}");
        }
        if a.print {
            println!("{}", s.to_text(&g));
        }
    }
    Ok(ExitCode::SUCCESS)
}

fn run_model(a: ModelArgs) -> anyhow::Result<ExitCode> {
    let g = a.src.grammar()?;
    let n = a.src.n.unwrap_or(g.n);
    let limits = a.src.limits();
    let name = a.name.clone().unwrap_or_else(|| g.name.clone());
    super::check_model_name(&name)?;
    let bank = if a.add { Some(super::bank_for_add(a.bank.clone())?) } else { None };
    let s = cpu_derive(&g, n, a.src.seed, &limits, None)?;
    let segs = turtle::interpret_parallel(&s, &g, limits.max_bytes)?;
    let model =
        mesh::build(&g, &segs, &mesh::ModelOptions { height: a.height.unwrap_or(g.height), ..Default::default() })?;
    let w = mesh::write(&a.out, &name, &g, &model)?;
    let (lo, hi) = model.bounds;
    println!(
        "{}: {} segments, {} leaf cards, {} triangles, bounds ({:.2}, {:.2}, {:.2})..({:.2}, {:.2}, {:.2}) m",
        w.gltf.display(),
        segs.len(),
        model.tips,
        w.triangles,
        lo.x,
        lo.y,
        lo.z,
        hi.x,
        hi.y,
        hi.z
    );
    if let Some(bank) = bank {
        let req = grove::bank::import::AddRequest {
            file: w.gltf.clone(),
            bank: bank.clone(),
            name: Some(name.clone()),
            species: Some(format!("lsystem-{}", g.name)),
            kind: None,
            far: None,
        };
        super::print_added(&grove::bank::import::add(&req)?, &bank);
    }
    Ok(ExitCode::SUCCESS)
}

fn best<T, E: Into<anyhow::Error>>(repeats: u32, mut f: impl FnMut() -> Result<T, E>) -> anyhow::Result<(f64, T)> {
    let mut best = f64::MAX;
    let mut last = None;
    for _ in 0..repeats.max(1) {
        drop(last.take());
        let t = Instant::now();
        let r = f().map_err(Into::into)?;
        best = best.min(t.elapsed().as_secs_f64() * 1e3);
        last = Some(r);
    }
    Ok((best, last.expect("at least one run")))
}

fn run_bench(a: BenchArgs) -> anyhow::Result<ExitCode> {
    let g = presets::preset(&a.preset)?;
    let limits = Limits::default();
    let gpu = if a.no_gpu { None } else { Some(GpuDeriver::new()?) };
    let pools: Vec<rayon::ThreadPool> =
        [1, 2].iter().map(|&t| rayon::ThreadPoolBuilder::new().num_threads(t).build()).collect::<Result<_, _>>()?;
    let bar = ProgressBar::new(a.n.len() as u64 * 6)
        .with_style(ProgressStyle::with_template("bench {bar:30} {pos}/{len} {msg}").expect("valid template"));
    let mut rows = Vec::new();
    for &n in &a.n {
        bar.set_message(format!("n = {n}"));
        let (d1, s) = best(a.repeats, || pools[0].install(|| derive::derive(&g, n, 0, &limits)))?;
        bar.inc(1);
        let hash = s.hash();
        drop(s);
        let (d2, s) = best(a.repeats, || pools[1].install(|| derive::derive(&g, n, 0, &limits)))?;
        bar.inc(1);
        let gpu_ms = match &gpu {
            Some(dev) => {
                let (t, gs) = best(a.repeats, || dev.derive(&g, n, 0, &limits))?;
                if gs.hash() != hash {
                    bail!("n = {n}: the GPU derivation differs from the CPU's");
                }
                Some(t)
            }
            None => None,
        };
        bar.inc(1);
        let symbols = s.len();
        let (ts, segs) = best(a.repeats, || turtle::interpret(&s, &g))?;
        let nseg = segs.len();
        drop(segs);
        bar.inc(1);
        let (t1, segs) = best(a.repeats, || pools[0].install(|| turtle::interpret_parallel(&s, &g, limits.max_bytes)))?;
        drop(segs);
        bar.inc(1);
        let (t2, segs) = best(a.repeats, || pools[1].install(|| turtle::interpret_parallel(&s, &g, limits.max_bytes)))?;
        drop(segs);
        drop(s);
        // The memoised turtle works from the grammar alone (deterministic grammars only).
        let (m1, m2) = if memo::applies(&g) {
            let (m1, segs) = best(a.repeats, || pools[0].install(|| memo::interpret_memo(&g, n, limits.max_bytes)))?;
            drop(segs);
            let (m2, segs) = best(a.repeats, || pools[1].install(|| memo::interpret_memo(&g, n, limits.max_bytes)))?;
            drop(segs);
            (Some(m1), Some(m2))
        } else {
            (None, None)
        };
        bar.inc(1);
        rows.push(serde_json::json!({
            "n": n, "symbols": symbols, "segments": nseg,
            "derive_ms_1_thread": d1, "derive_ms_2_threads": d2, "derive_ms_gpu": gpu_ms,
            "interpret_ms_sequential": ts, "interpret_ms_1_thread": t1, "interpret_ms_2_threads": t2,
            "interpret_ms_memo_1_thread": m1, "interpret_ms_memo_2_threads": m2,
        }));
    }
    bar.finish_and_clear();
    let adapter = gpu.as_ref().map(|d| d.adapter().to_string());
    if a.json {
        println!("{}", serde_json::json!({"preset": a.preset, "repeats": a.repeats, "gpu": adapter, "rows": rows}));
        return Ok(ExitCode::SUCCESS);
    }
    println!("{} (fastest of {}; GPU: {})", a.preset, a.repeats, adapter.as_deref().unwrap_or("not run"));
    println!(
        "| n | symbols | segments | derive 1 thread | derive 2 threads | derive GPU | interpret sequential | interpret 1 thread | interpret 2 threads | memoised 1 thread | memoised 2 threads |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|");
    let ms = |v: &serde_json::Value| v.as_f64().map(|x| format!("{x:.1} ms")).unwrap_or_else(|| "—".into());
    for r in &rows {
        println!(
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
            r["n"],
            r["symbols"],
            r["segments"],
            ms(&r["derive_ms_1_thread"]),
            ms(&r["derive_ms_2_threads"]),
            ms(&r["derive_ms_gpu"]),
            ms(&r["interpret_ms_sequential"]),
            ms(&r["interpret_ms_1_thread"]),
            ms(&r["interpret_ms_2_threads"]),
            ms(&r["interpret_ms_memo_1_thread"]),
            ms(&r["interpret_ms_memo_2_threads"])
        );
    }
    Ok(ExitCode::SUCCESS)
}
