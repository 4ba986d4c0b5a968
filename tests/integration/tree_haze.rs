//! Trees fade into the distance as the ground does (issue #37: the terrain fades into the sky
//! with aerial perspective; a forest whose far trees stayed at full contrast stood as a dark
//! band on the faded ground at the horizon).
//!
//! One tree against the sky, seen level from 30 m and from 450 m with the field of view fitted
//! to its bounding sphere, so that it covers the same pixels from both. Without the haze the two
//! images would show the same tree in the same colours; with it (lighting.wgsl `haze_at`: none
//! within 40 m, about 64 % at 450 m) the far tree's mean colour lies much nearer the sky's
//! behind it. Checked for the mesh and for the impostor. On whatever adapter wgpu finds
//! (lavapipe in CI); without one the test fails loudly.

use glam::Vec3;
use grove::models::{ModelData, load_model};
use grove::render::offscreen::Gpu;
use grove_systems::Sim;
use image::RgbaImage;

const SIZE: u32 = 128;

use crate::shared_gpu;
use shared_gpu::LOCK;

fn gpu() -> &'static Gpu {
    shared_gpu::shared_gpu("tree haze tests")
}

use crate::sky_stage;

/// One tree of `data` against the sky, seen level from `distance` metres south of its bounds'
/// centre, the field of view fitted to its bounding sphere.
fn stage(data: &ModelData, distance: f32) -> Sim {
    sky_stage::stage(data, Vec3::Z, distance).0
}

/// `sim` rendered with the model loaded (or not), no shadows, every leaf, and every tree an
/// impostor (`impostor`) or none.
fn draw(data: &ModelData, sim: &Sim, with_model: bool, impostor: bool) -> RgbaImage {
    draw_counted(data, sim, with_model, impostor).0
}

/// [`draw`], with the tree instances the main view drew.
fn draw_counted(data: &ModelData, sim: &Sim, with_model: bool, impostor: bool) -> (RgbaImage, usize) {
    let _guard = LOCK.lock().unwrap_or_else(|e| e.into_inner());
    sky_stage::draw(gpu(), data, sim, with_model, SIZE, if impostor { 1.0e6 } else { 0.0 })
}

/// The mean colour of the tree's pixels (those that differ from the render without it by more
/// than 4 in some channel: elsewhere the two renders agree exactly) and of the sky behind them,
/// and how many there are.
fn tree_and_sky(tree: &RgbaImage, sky: &RgbaImage) -> ([f64; 3], [f64; 3], usize) {
    let (mut t, mut s, mut n) = ([0.0; 3], [0.0; 3], 0usize);
    for (a, b) in tree.pixels().zip(sky.pixels()) {
        if (0..3).any(|c| a.0[c].abs_diff(b.0[c]) > 4) {
            for c in 0..3 {
                t[c] += f64::from(a.0[c]);
                s[c] += f64::from(b.0[c]);
            }
            n += 1;
        }
    }
    let k = n.max(1) as f64;
    (t.map(|v| v / k), s.map(|v| v / k), n)
}

fn distance(a: [f64; 3], b: [f64; 3]) -> f64 {
    (0..3).map(|c| (a[c] - b[c]).powi(2)).sum::<f64>().sqrt()
}

fn broadleaf() -> ModelData {
    let path = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("assets/trees/broadleaf-mesh.gltf");
    load_model(&path).unwrap()
}

#[test]
fn a_far_tree_fades_towards_the_sky_as_the_ground_does() {
    let data = broadleaf();
    for impostor in [false, true] {
        let kind = if impostor { "impostor" } else { "mesh" };
        let mut contrast = Vec::new();
        for d in [30.0f32, 450.0] {
            let sim = stage(&data, d);
            let (tree, sky, n) = tree_and_sky(&draw(&data, &sim, true, impostor), &draw(&data, &sim, false, impostor));
            assert!(n > (SIZE * SIZE / 20) as usize, "{kind} at {d} m: only {n} pixels show the tree");
            eprintln!("{kind} at {d} m: tree {tree:.1?}, sky behind it {sky:.1?}, {n} pixels");
            contrast.push(distance(tree, sky));
        }
        // The near tree stands out from the sky; the far one, as large on screen, far less.
        assert!(contrast[0] > 40.0, "{kind}: the near tree differs from the sky by only {:.1}", contrast[0]);
        assert!(
            contrast[1] < 0.6 * contrast[0],
            "{kind}: the tree at 450 m differs from the sky behind it by {:.1}, at 30 m by {:.1}: it does not fade",
            contrast[1],
            contrast[0]
        );
    }
}

/// A tree lost in the haze (`HIDDEN_IN_HAZE`: 97 % of it, from about 566 m) is not drawn, and
/// that is invisible: at 560 m, just short of it, the tree is drawn yet no pixel differs from the
/// sky behind it by more than 4 of 255, while at 500 m it still shows.
#[test]
fn a_tree_lost_in_the_haze_is_not_drawn() {
    use grove::render::haze::haze_share;
    use grove::render::trees::instances::HIDDEN_IN_HAZE;
    let data = broadleaf();
    assert!(haze_share(560.0) < HIDDEN_IN_HAZE && haze_share(575.0) >= HIDDEN_IN_HAZE);
    for impostor in [false, true] {
        let kind = if impostor { "impostor" } else { "mesh" };
        // The trees drawn and the pixels that differ from the sky by more than 4 in a channel.
        let seen = |d: f32| {
            let sim = stage(&data, d);
            let ((tree, drawn), sky) = (draw_counted(&data, &sim, true, impostor), draw(&data, &sim, false, impostor));
            let (_, _, n) = tree_and_sky(&tree, &sky);
            eprintln!("{kind} at {d} m: {drawn} trees drawn, {n} pixels differ from the sky");
            (drawn, n)
        };
        let (drawn, shown) = seen(500.0);
        assert!(
            drawn == 1 && shown > (SIZE * SIZE / 40) as usize,
            "{kind}: at 500 m the tree should still show ({drawn} drawn, {shown} pixels)"
        );
        assert_eq!(seen(560.0), (1, 0), "{kind}: at 560 m the tree is drawn and shows no more than the haze");
        assert_eq!(seen(575.0), (0, 0), "{kind}: the tree lost in the haze at 575 m is drawn");
    }
}
