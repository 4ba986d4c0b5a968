//! `grove scene check`: validate a scene file and print a summary.

pub mod sim;
pub mod sun;

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::anyhow;
use clap::Subcommand;
use grove_systems::Sim;

/// Subcommands of `grove scene`.
#[derive(Subcommand)]
pub enum SceneCommand {
    /// Validate a scene file and print a summary of what it holds.
    Check {
        /// The scene file (RON).
        file: PathBuf,
    },
}

/// Runs `grove scene ...`.
pub fn run(cmd: SceneCommand) -> anyhow::Result<ExitCode> {
    match cmd {
        SceneCommand::Check { file } => {
            let scene = crate::cli::load_scene(&file)?;
            let sim = Sim::from_scene(&scene, scene.seed).map_err(|e| anyhow!("{}: {e}", file.display()))?;
            println!("{}: ok, scene '{}'", file.display(), scene.name);
            println!("  dt: {:.6} s ({:.1} Hz), seed {}", scene.dt, 1.0 / scene.dt, scene.seed);
            sim.for_each_plane(|_, p| {
                let (min, max) =
                    p.vertices.iter().fold((glam::Vec3::MAX, glam::Vec3::MIN), |(a, b), v| (a.min(*v), b.max(*v)));
                println!(
                    "  plane '{}': {} vertices, {} triangles, x {:.1}..{:.1} m, y {:.2}..{:.2} m, z {:.1}..{:.1} m",
                    p.name,
                    p.vertices.len(),
                    p.triangles.len(),
                    min.x,
                    max.x,
                    min.y,
                    max.y,
                    min.z,
                    max.z
                );
            });
            let s = &scene.sun;
            println!(
                "  sun: {:.4}° N, {:.4}° E at {} (time rate {})",
                s.latitude_deg, s.longitude_deg, s.utc, s.time_rate
            );
            let w = &scene.wind;
            println!(
                "  wind: strength {}, density {}/m, gusts {} ± {} at {} Hz",
                w.strength, w.density, w.gust_average, w.gust_strength, w.gust_frequency
            );
            println!("  trees: {}", scene.trees.len());
            for w in &scene.water {
                let area = grove_systems::water::signed_area(&w.polygon).abs();
                println!(
                    "  water '{}': {} vertices, {area:.1} m², surface at {:.2} m, {:.2} m deep",
                    w.name,
                    w.polygon.len(),
                    w.height,
                    w.depth
                );
            }
            for g in &scene.grass {
                println!(
                    "  grass '{}': {:?}, {} per m², {:.2}..{:.2} m tall, over about {:.0} m²",
                    g.name,
                    g.kind,
                    g.density,
                    g.height.0,
                    g.height.1,
                    g.area_on(&scene.plane_outlines())
                );
            }
            let c = &scene.camera;
            println!(
                "  camera: at {:?} looking at {:?}, fov {}°",
                c.position.to_array(),
                c.look_at.to_array(),
                c.fov_y_deg
            );
            Ok(ExitCode::SUCCESS)
        }
    }
}
