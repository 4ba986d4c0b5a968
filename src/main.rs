//! The `grove` command-line tool: headless simulation and replays, the study and its reports,
//! rendering, assets, the desktop app and benchmarks.
//!
//! Each subcommand lives in its own module under `cli/`. Errors are printed as one line on
//! stderr (`error: ...`) with a non-zero exit code; nothing the user types can cause a panic.

use std::process::ExitCode;

use clap::{Parser, Subcommand};

mod cli;
mod desktop;
mod techniques;

/// grove: a deterministic simulation of a tree-planting study.
#[derive(Parser)]
#[command(name = "grove", version, about, long_about = None, propagate_version = true)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run a scene headless for a number of ticks and print its world hash.
    Sim(cli::scene::sim::SimArgs),
    /// Work with scene files.
    #[command(subcommand)]
    Scene(cli::scene::SceneCommand),
    /// Measure grove's speed (sim tick, ray casts, wind, replay, study, rendering) and print JSON.
    Bench(cli::bench::BenchArgs),
    /// Re-simulate a recording headless and verify its checkpoints (exit 0 verified, 1 diverged, 2 bad input).
    Replay(cli::replay::ReplayArgs),
    /// Run scenario files headless in parallel, one line each (exit 0 all passed, 1 a failure, 2 bad file).
    Test(cli::test::TestArgs),
    /// Scenario files: draft one from a recording.
    #[command(subcommand)]
    Scenario(cli::test::scenario::ScenarioCommand),
    /// Re-simulate the study's recordings, verify them and write the reports (the main job).
    Study(cli::study::StudyArgs),
    /// Generate synthetic participants' recordings of the study's tasks.
    Synth(cli::study::synth::SynthArgs),
    /// Plant trees interactively in a window (mouse, keyboard or gamepad), optionally recorded.
    Play(cli::play::PlayArgs),
    /// View a recording in a window: play, pause, step, seek, with event markers.
    View(cli::play::view::ViewArgs),
    /// Print the sun's position (NREL SPA) for a place and a UTC time.
    Sun(cli::scene::sun::SunArgs),
    /// Regenerate the tree models, textures, catalogue and sky cubemap (deterministic).
    Assets(cli::models::assets::AssetsArgs),
    /// Render a scene, a frame sequence or a glTF model to PNG (offscreen).
    Render(cli::render::RenderArgs),
    /// L-system trees: derive (CPU or GPU), write glTF models, benchmark.
    #[command(subcommand)]
    Lsystem(cli::models::lsystem::LsystemCommand),
    /// Parametric trees after Weber and Penn from species presets: generate glTF models (docs/species.md).
    #[command(subcommand)]
    Trees(cli::models::trees::TreesCommand),
    /// The model bank: add glTF models, list and check banks (docs/model-bank.md).
    #[command(subcommand)]
    Models(cli::models::ModelsCommand),
    /// Treetops from summer and winter aerial photographs: segment, scene, synth, eval.
    #[command(subcommand)]
    Aerial(cli::aerial::AerialCommand),
    /// A session server: recordings streamed from any device, checked line by line, verified as they end (docs/serve.md).
    Serve(cli::serve::ServeArgs),
}

fn main() -> ExitCode {
    cli::install_panic_hook();
    cli::quiet_on_closed_pipe();
    if let Err(e) = techniques::install_all() {
        eprintln!("error: {e}");
        return ExitCode::from(2);
    }
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => {
            // clap prints help and version to stdout with exit code 0; a usage error is one
            // line on stderr with exit code 2 (`--help` has the rest).
            if !e.use_stderr() {
                let _ = e.print();
                return ExitCode::SUCCESS;
            }
            eprintln!("{}", cli::usage_error_line(&e));
            return ExitCode::from(2);
        }
    };
    let result = match cli.command {
        Command::Sim(args) => cli::scene::sim::run(args),
        Command::Scene(cmd) => cli::scene::run(cmd),
        Command::Bench(args) => cli::bench::run(args),
        Command::Replay(args) => cli::replay::run(args),
        Command::Test(args) => cli::test::run(args),
        Command::Scenario(cmd) => cli::test::scenario::run(cmd),
        Command::Study(args) => cli::study::run(args),
        Command::Synth(args) => cli::study::synth::run(args),
        Command::Play(args) => cli::play::run(args),
        Command::View(args) => cli::play::view::run(args),
        Command::Sun(args) => cli::scene::sun::run(args),
        Command::Assets(args) => cli::models::assets::run(args),
        Command::Render(args) if args.video.is_some() => cli::render::video::run(args),
        Command::Render(args) => cli::render::run(args),
        Command::Lsystem(cmd) => cli::models::lsystem::run(cmd),
        Command::Aerial(cmd) => cli::aerial::run(cmd),
        Command::Models(cmd) => cli::models::run(cmd),
        Command::Trees(cmd) => cli::models::trees::run(cmd),
        Command::Serve(args) => cli::serve::run(args),
    };
    match result {
        Ok(code) => code,
        Err(e) => {
            eprintln!("error: {}", cli::one_line(&e));
            ExitCode::from(2)
        }
    }
}
