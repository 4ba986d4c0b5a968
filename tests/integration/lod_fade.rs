//! No popping between a tree's levels of detail: the camera flies away from a shipped species
//! tree (the bank's oak, its level 1 with level 2 as its far model) through the distance where
//! level 2 takes over, one frame at a time, with shadows. Each step of the flight changes some of
//! the tree's pixels whatever the levels do, as its leaves shrink on screen; so each step is
//! compared with the same step of the flight drawn with level 1 alone and with level 2 alone.
//! With the cross-fade (`RenderOptions::lod_cross_fade`, the default) no step changes much more
//! than the larger of those; with it off, the step where the levels switch does, which shows
//! that the check can fail.

use glam::Vec3;
use grove::models::{ModelData, load_model};
use grove::render::Renderer;
use grove::render::offscreen;
use grove_systems::Sim;
use grove_systems::catalogue::ModelId;
use grove_systems::components::{Head, Pose};
use image::RgbaImage;

use crate::shared_gpu::{self, LOCK};
use crate::sky_stage::stage;

const SIZE: u32 = 256;
/// The threshold of level 2, pixels of the bounding sphere's diameter (the band above it
/// reaches 1.25 times as far): smaller than the default, so that the tree fits a small image.
const FAR_PIXELS: f32 = 240.0;
const FRAMES: usize = 40;
/// The bound on a step's change over the larger of the single levels' changes at that step.
const BOUND: f64 = 1.35;

fn bank_model(name: &str) -> ModelData {
    let path = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("assets/banks/species")
        .join(name)
        .join(format!("{name}.gltf"));
    load_model(&path).unwrap()
}

/// How the flight draws the tree.
#[derive(Clone, Copy, PartialEq)]
enum Levels {
    /// No tree: the sky behind it.
    None,
    /// Level 1 alone (no far model drawn).
    Near,
    /// Level 2 alone (the far model at every size).
    Far,
    /// Level 1, then level 2 below `FAR_PIXELS`, with or without the cross-fade.
    Both { cross_fade: bool },
}

/// The flight: the tree seen from each of `distances` metres (from its base) along `dir`, with
/// a fixed field of view `fov`, every leaf drawn, no impostors.
fn fly(
    near: &ModelData,
    far: &ModelData,
    sim: &mut Sim,
    distances: &[f32],
    dir: Vec3,
    fov: f32,
    levels: Levels,
) -> Vec<RgbaImage> {
    let _guard = LOCK.lock().unwrap_or_else(|e| e.into_inner());
    let g = shared_gpu::shared_gpu("the level-of-detail cross-fade test");
    let mut r =
        Renderer::empty(&g.device, &g.queue, offscreen::FORMAT, SIZE, SIZE, &grove::render::default_assets_dir())
            .unwrap();
    if levels != Levels::None {
        r.features.trees.set_model(ModelId(0), near);
        r.features.trees.set_model(ModelId(1), far);
        r.features.trees.set_far(ModelId(0), Some(ModelId(1)));
    }
    r.options.leaf_pixels = 0.0;
    r.options.impostor_pixels = 0.0;
    r.options.far_pixels = match levels {
        Levels::Near => 0.0,
        Levels::Far => 1.0e9,
        _ => FAR_PIXELS,
    };
    r.options.lod_cross_fade = levels != Levels::Both { cross_fade: false };
    let (lo, hi) = near.bounds;
    let centre = (lo + hi) * 0.5;
    distances
        .iter()
        .map(|&d| {
            sim.set_up().camera(Head { pose: Pose::looking_at(dir * d, centre), fov_y: fov });
            offscreen::render_image(g, &mut r, sim).unwrap()
        })
        .collect()
}

/// The share of the tree's pixels (`tree_pixels` of them) that differ by more than 40 in some
/// channel between `a` and `b`.
fn changed(a: &RgbaImage, b: &RgbaImage, tree_pixels: f64) -> f64 {
    a.pixels().zip(b.pixels()).filter(|(p, q)| (0..3).any(|c| p.0[c].abs_diff(q.0[c]) > 40)).count() as f64
        / tree_pixels
}

fn steps(frames: &[RgbaImage], tree_pixels: f64) -> Vec<f64> {
    frames.windows(2).map(|w| changed(&w[0], &w[1], tree_pixels)).collect()
}

#[test]
fn flying_through_the_switch_to_level_two_does_not_pop() {
    let near = bank_model("oak-lod1");
    let far = bank_model("oak-lod2");
    let dir = Vec3::new(0.0, 0.15, 1.0).normalize();
    let (mut sim, _) = stage(&near, dir, 60.0);
    // The bounding sphere the renderer measures: about the tree's base.
    let radius = near.bounds.0.abs().max(near.bounds.1.abs()).length();
    let fov = 30f32.to_radians();
    let ppr = SIZE as f32 * 0.5 / (fov * 0.5).tan();
    // From 4 % above the band (240 → 300 px) to 4 % below its foot, in equal ratios.
    let (start, end) = (FAR_PIXELS * 1.25 * 1.04, FAR_PIXELS * 0.96);
    let distances: Vec<f32> = (0..FRAMES)
        .map(|k| 2.0 * radius * ppr / (start * (end / start).powf(k as f32 / (FRAMES - 1) as f32)))
        .collect();

    let mut flight = |levels| fly(&near, &far, &mut sim, &distances, dir, fov, levels);
    let background = flight(Levels::None);
    let near_only = flight(Levels::Near);
    let far_only = flight(Levels::Far);
    let on = flight(Levels::Both { cross_fade: true });
    let off = flight(Levels::Both { cross_fade: false });
    // The flight starts with level 1 alone and ends with level 2 alone, either way.
    for frames in [&on, &off] {
        assert!(frames[0] == near_only[0], "the first frame should be level 1 alone");
        assert!(frames[FRAMES - 1] == far_only[FRAMES - 1], "the last frame should be level 2 alone");
    }
    // The tree's pixels: those of the first or the last frame that are not the sky's.
    let tree = |a: &RgbaImage, b: &RgbaImage| {
        a.pixels().zip(b.pixels()).filter(|(p, q)| (0..3).any(|c| p.0[c].abs_diff(q.0[c]) > 30)).count()
    };
    let tree_pixels = (tree(&on[0], &background[0]) + tree(&on[FRAMES - 1], &background[FRAMES - 1])) as f64 / 2.0;
    assert!(tree_pixels > 2000.0, "the tree should be seen ({tree_pixels} px)");
    let whole = changed(&near_only[FRAMES / 2], &far_only[FRAMES / 2], tree_pixels);
    let (n, f) = (steps(&near_only, tree_pixels), steps(&far_only, tree_pixels));
    // Each step's change over the flight's own change at that step.
    let excess = |frames: &[RgbaImage]| -> Vec<f64> {
        steps(frames, tree_pixels).iter().zip(n.iter().zip(&f)).map(|(s, (a, b))| s / a.max(*b)).collect()
    };
    let (on_excess, off_excess) = (excess(&on), excess(&off));
    let worst = |e: &[f64]| e.iter().copied().fold(0.0, f64::max);
    let list = |e: &[f64]| e.iter().map(|x| format!("{x:.2}")).collect::<Vec<_>>().join(" ");
    eprintln!(
        "tree {tree_pixels} px; level 1 against level 2: {:.1} % of it; a step of level 1 alone changes {:.1} to {:.1} %",
        whole * 100.0,
        n.iter().copied().fold(1.0, f64::min) * 100.0,
        worst(&n) * 100.0
    );
    eprintln!("steps over the single levels' with the cross-fade: {}", list(&on_excess));
    eprintln!("steps over the single levels' without it: {}", list(&off_excess));
    assert!(whole > 0.15, "the levels should differ enough to pop ({:.1} % of the tree)", whole * 100.0);
    assert!(
        worst(&on_excess) <= BOUND,
        "with the cross-fade a step changes {:.2} times what the flight alone does",
        worst(&on_excess)
    );
    assert!(
        worst(&off_excess) > BOUND,
        "without the cross-fade the check should fail, but its worst step is {:.2}",
        worst(&off_excess)
    );
}
