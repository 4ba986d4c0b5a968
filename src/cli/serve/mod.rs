//! `grove serve`: the session server (`docs/serve.md`), `grove serve push` and `grove serve bench`.

use std::net::IpAddr;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Duration;

use anyhow::{bail, Context};
use clap::{Args, Subcommand};
use grove::serve::client::{bench::BenchOptions, push::PushOptions, push::Rate};
use grove::serve::{self, ServeConfig, TlsChoice};

/// `grove serve` and its subcommands.
#[derive(Args)]
#[command(args_conflicts_with_subcommands = true)]
pub struct ServeArgs {
    #[command(subcommand)]
    command: Option<ServeCommand>,
    /// The folder sessions are written to (made if missing): DIR/<participant>-<task>-<n>.jsonl and DIR/sessions.json.
    #[arg(long, default_value = "sessions")]
    out: PathBuf,
    /// The address to listen on; any address other than a loopback one needs the session token printed at start.
    #[arg(long, default_value = "127.0.0.1")]
    host: IpAddr,
    /// The port (0: any free port, printed).
    #[arg(long, default_value_t = 8080)]
    port: u16,
    /// TLS: 'auto' (a self-signed certificate kept in DIR/tls/) or 'CERT,KEY' (PEM files).
    #[arg(long)]
    tls: Option<String>,
    /// A model bank whose models headers may name (and which is served); repeatable.
    #[arg(long)]
    bank: Vec<PathBuf>,
    /// The web folder: dist/ (the page, at /), client/ (at /client/), sim/ (the module's loader, at /sim/).
    #[arg(long, default_value = "web")]
    web: PathBuf,
    /// The folder with the built module grove_sim.wasm (bash web/build.sh; default: $CARGO_TARGET_DIR/wasm or target/wasm), served at /target/wasm/.
    #[arg(long)]
    wasm: Option<PathBuf>,
    /// The assets folder: scenes/, tasks/, trees/, controllers/ and banks/ are served.
    #[arg(long, default_value = "assets")]
    assets: PathBuf,
    /// Seconds a request's head, TLS handshake or body may take to arrive before it is refused.
    #[arg(long, default_value_t = 20.0, value_name = "SECONDS")]
    read_timeout: f64,
    /// Seconds after a client's last request before another client may write its session.
    #[arg(long, default_value_t = 30.0, value_name = "SECONDS")]
    writer_lease: f64,
    /// Seconds without a request after which a session is ended as abandoned and verified.
    #[arg(long, default_value_t = 600.0, value_name = "SECONDS")]
    abandon_after: f64,
    /// The most sessions open at once.
    #[arg(long, default_value_t = 256)]
    max_sessions: usize,
    /// The most connections served at once; a new one closes the one idle longest (while all are busy, it waits).
    #[arg(long, default_value_t = 512)]
    max_connections: usize,
    /// The most connections from one address; a new one closes that address's one idle longest (while all are busy, it is closed).
    #[arg(long, default_value_t = 256)]
    max_connections_per_address: usize,
    /// Ask for the token on a loopback address too.
    #[arg(long)]
    require_token: bool,
    /// Verify every session as it streams ('on'), or only at its end, re-simulating its file ('off': for comparisons).
    #[arg(long, default_value = "on", value_parser = ["on", "off"])]
    live: String,
    /// Draw a new token instead of the one kept in DIR/token (clients with the old one are then refused).
    #[arg(long)]
    new_token: bool,
    /// Run a study protocol (docs/protocol.md, e.g. assets/protocols/tree-planting.ron): participant ids, condition orders, the page /protocol, answers in DIR/<id>.answers.jsonl, the live page /dashboard.
    #[arg(long, value_name = "FILE")]
    protocol: Option<PathBuf>,
}

#[derive(Subcommand)]
enum ServeCommand {
    /// Stream a recording to a server as a live client would (a lab's network test).
    Push(PushArgs),
    /// Many sessions at once against a server of its own on loopback (or --to URL): acknowledgement times, how soon each checkpoint is verified live, server CPU and memory (JSON).
    Bench(BenchArgs),
}

#[derive(Args)]
struct PushArgs {
    /// The recording to send.
    file: PathBuf,
    /// The server's URL as grove serve printed it (with its ?token= on a LAN).
    #[arg(long)]
    to: String,
    /// 'max' (as fast as acknowledged), 'real' (at the pace of the events' times) or a factor of real time such as 10.
    #[arg(long, default_value = "max")]
    rate: String,
    /// The server's certificate to trust for an https URL (grove serve --tls auto writes DIR/tls/cert.pem).
    #[arg(long)]
    ca: Option<PathBuf>,
    /// Seconds one request may take before the connection counts as lost.
    #[arg(long, default_value_t = 10.0, value_name = "SECONDS")]
    timeout: f64,
    /// Seconds without reaching the server after which the push gives up.
    #[arg(long, default_value_t = 300.0, value_name = "SECONDS")]
    give_up: f64,
    /// Print the result as JSON.
    #[arg(long)]
    json: bool,
}

#[derive(Args)]
struct BenchArgs {
    /// Sessions streaming at once.
    #[arg(long, default_value_t = 50)]
    sessions: usize,
    /// Seconds each session streams (the figures in docs/benchmarks.md: 60).
    #[arg(long, default_value_t = 60.0)]
    seconds: f64,
    /// A server already running, on this machine or another (its URL as grove serve printed it, with its ?token=): streamed to in place of a server of the bench's own, whose CPU and memory are then not read.
    #[arg(long)]
    to: Option<String>,
    /// The server's certificate to trust for an https --to URL (grove serve --tls auto writes DIR/tls/cert.pem).
    #[arg(long, requires = "to")]
    ca: Option<PathBuf>,
    /// Its own server's live verification, 'on' or 'off' (a comparison: sessions then verified only at their end).
    #[arg(long, default_value = "on", value_parser = ["on", "off"], conflicts_with = "to")]
    live: String,
}

fn seconds(name: &str, s: f64) -> anyhow::Result<Duration> {
    if !(s.is_finite() && s > 0.0 && s <= 1e6) {
        bail!("--{name} must be a number of seconds above 0");
    }
    Ok(Duration::from_secs_f64(s))
}

fn runtime() -> anyhow::Result<tokio::runtime::Runtime> {
    Ok(tokio::runtime::Builder::new_multi_thread().enable_all().build()?)
}

/// Runs `grove serve …`.
pub fn run(args: ServeArgs) -> anyhow::Result<ExitCode> {
    match args.command {
        Some(ServeCommand::Push(p)) => push(p),
        Some(ServeCommand::Bench(b)) => bench(b),
        None => {
            let tls = match args.tls.as_deref() {
                None => TlsChoice::Off,
                Some("auto") => TlsChoice::Auto,
                Some(pair) => match pair.split_once(',') {
                    Some((c, k)) if !c.is_empty() && !k.is_empty() => TlsChoice::Files { cert: c.into(), key: k.into() },
                    _ => bail!("--tls takes 'auto' or 'CERT,KEY' (two PEM files)"),
                },
            };
            if args.new_token && !args.require_token && args.host.is_loopback() {
                bail!("--new-token is for a server that asks for a token: a network address (--host) or --require-token");
            }
            if args.max_sessions == 0 || args.max_connections == 0 || args.max_connections_per_address == 0 {
                bail!("--max-sessions, --max-connections and --max-connections-per-address must be at least 1");
            }
            let protocol = match &args.protocol {
                Some(p) => Some(grove::protocol::load(p)?),
                None => None,
            };
            let config = ServeConfig {
                out: args.out,
                host: args.host,
                port: args.port,
                tls,
                banks: grove_systems::bank::bank_dirs(&args.bank, std::env::var(grove_systems::bank::BANK_ENV).ok().as_deref()),
                web: args.web,
                wasm: args.wasm.unwrap_or_else(|| PathBuf::from(std::env::var("CARGO_TARGET_DIR").unwrap_or_else(|_| "target".into())).join("wasm")),
                assets: args.assets,
                read_timeout: seconds("read-timeout", args.read_timeout)?,
                writer_lease: seconds("writer-lease", args.writer_lease)?,
                abandon_after: seconds("abandon-after", args.abandon_after)?,
                max_sessions: args.max_sessions,
                max_connections: args.max_connections,
                max_per_address: args.max_connections_per_address,
                require_token: args.require_token,
                new_token: args.new_token,
                protocol,
                live: args.live == "on",
            };
            serve::run(config)?;
            Ok(ExitCode::SUCCESS)
        }
    }
}

fn push(p: PushArgs) -> anyhow::Result<ExitCode> {
    let rate = match p.rate.as_str() {
        "max" => Rate::Max,
        "real" => Rate::Real(1.0),
        f => match f.parse::<f64>() {
            Ok(x) if x.is_finite() && x > 0.0 => Rate::Real(x),
            _ => bail!("--rate takes 'max', 'real' or a factor of real time above 0, such as 10"),
        },
    };
    let options = PushOptions { rate, timeout: seconds("timeout", p.timeout)?, give_up: seconds("give-up", p.give_up)?, max_batch_bytes: 256 * 1024 };
    let endpoint = serve::client::conn::Endpoint::parse(&p.to, p.ca.as_deref())?;
    let say = |m: &str| eprintln!("{}: {m}", p.file.display());
    let report = runtime()?.block_on(serve::client::push::push(&p.file, &endpoint, &options, &say))?;
    let status = report.status();
    let shown = status.map_or("?", |s| s.as_str());
    if p.json {
        crate::cli::print_json(&report)?;
    } else {
        let continued = if report.continued_from > 1 { format!(", continued from line {}", report.continued_from + 1) } else { String::new() };
        println!(
            "{}: {} lines pushed in {:.2} s ({} requests, {} reconnects{continued}) to {} (session {}): {}",
            report.file, report.lines, report.seconds, report.requests, report.reconnects, report.server_file, report.session, shown
        );
    }
    Ok(if status.is_some_and(|s| s.failed()) { ExitCode::from(1) } else { ExitCode::SUCCESS })
}

fn bench(b: BenchArgs) -> anyhow::Result<ExitCode> {
    if b.sessions == 0 || b.sessions > 1000 {
        bail!("--sessions must be 1 to 1000");
    }
    seconds("seconds", b.seconds)?;
    let grove = std::env::current_exe().context("cannot find the grove program to start the server")?;
    let to = match &b.to {
        Some(url) => Some(serve::client::conn::Endpoint::parse(url, b.ca.as_deref())?),
        None => None,
    };
    let options = BenchOptions { sessions: b.sessions, seconds: b.seconds, grove, to, live: b.live == "on" };
    let say = |m: &str| eprintln!("serve bench: {m}");
    let mut report = runtime()?.block_on(serve::client::bench::bench(&options, &say))?;
    if let Some(o) = report.as_object_mut() {
        o.insert("build".into(), serde_json::json!(if cfg!(debug_assertions) { "debug" } else { "release" }));
        o.insert("threads".into(), serde_json::json!(std::thread::available_parallelism().map_or(1, |n| n.get())));
    }
    crate::cli::print_json(&report)?;
    Ok(ExitCode::SUCCESS)
}
