//! The horizon (issue #37): the terrain meets the sky without a band, from eye height and from
//! above. The terrain ends at the far plane (600 m); below the horizon beyond it the sky is
//! drawn, and it must be what the faded terrain there would be, the sky's colour at the horizon,
//! not the environment cubemap's ground (a grey-brown band, worst from above, where it once
//! filled the top ninth of an aerial scene's default view).
//!
//! Each test renders the study scene on whatever adapter wgpu finds (lavapipe in CI) and reads
//! the mean colour of each row over a stretch of columns with nothing but ground and sky in
//! them. Without an adapter every test fails loudly.

use std::path::PathBuf;

use glam::Vec3;
use grove::render::offscreen::{self, Gpu};
use grove::render::{Camera, Renderer, camera_matrix};
use grove_systems::Sim;
use grove_systems::components::{Head, Pose};
use grove_systems::scene::Scene;
use image::RgbaImage;

use crate::shared_gpu;
use shared_gpu::LOCK;

fn gpu() -> &'static Gpu {
    shared_gpu::shared_gpu("horizon tests")
}

fn study() -> Sim {
    let scene = Scene::load(&PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/study.ron")).unwrap();
    Sim::from_scene(&scene, scene.seed).unwrap()
}

fn render(sim: &Sim, w: u32, h: u32) -> RgbaImage {
    let _guard = LOCK.lock().unwrap_or_else(|e| e.into_inner());
    let g = gpu();
    let mut r = Renderer::new(&g.device, &g.queue, offscreen::FORMAT, w, h).unwrap();
    offscreen::render_image(g, &mut r, sim).unwrap()
}

/// The camera of `sim` (its head).
fn camera(sim: &Sim) -> Camera {
    let head = sim.head();
    Camera { position: head.pose.position, rotation: head.pose.rotation, fov_y: head.fov_y }
}

/// The row of the horizon straight ahead in a `w` × `h` image (fractional; may lie outside it).
fn horizon_row(sim: &Sim, w: u32, h: u32) -> f32 {
    let c = camera(sim);
    let ahead = c.rotation * Vec3::NEG_Z;
    let far = c.position + Vec3::new(ahead.x, 0.0, ahead.z).normalize() * 1.0e6;
    let q = camera_matrix(&c, w as f32 / h as f32).project_point3(far);
    (0.5 - q.y * 0.5) * h as f32
}

/// The mean colour (0..255 per channel) of each of `rows`, over the columns `cols`.
fn row_means(img: &RgbaImage, cols: std::ops::Range<u32>, rows: std::ops::Range<u32>) -> Vec<[f64; 3]> {
    rows.map(|y| {
        let mut sum = [0.0; 3];
        for x in cols.clone() {
            let p = img.get_pixel(x, y).0;
            for c in 0..3 {
                sum[c] += f64::from(p[c]);
            }
        }
        sum.map(|s| s / cols.len() as f64)
    })
    .collect()
}

/// Fails if, going from the first row (the sky's side) to the last (the terrain's), some row is
/// darker in a channel by more than `tol` than both a row before it and a row after it: a band
/// between the sky and the terrain. (The sky may darken away from the horizon and the terrain
/// away from it too; only a dip between them is a band.)
fn assert_no_dark_band(what: &str, rows: &[[f64; 3]], first_row: u32, tol: f64) {
    for c in 0..3 {
        for i in 1..rows.len().saturating_sub(1) {
            let v = rows[i][c];
            let above = rows[..i].iter().map(|r| r[c]).fold(f64::MIN, f64::max);
            let below = rows[i + 1..].iter().map(|r| r[c]).fold(f64::MIN, f64::max);
            assert!(
                !(v + tol < above && v + tol < below),
                "{what}: row {} is a band, channel {c} at {v:.1} below both the sky ({above:.1}) and the terrain ({below:.1}); rows {rows:.0?}",
                first_row as usize + i
            );
        }
    }
}

#[test]
fn from_eye_height_the_terrain_meets_the_sky_without_a_band() {
    // The study's own camera: 1.7 m up, looking north and a little down.
    let sim = study();
    let (w, h) = (480, 270);
    let img = render(&sim, w, h);
    let horizon = horizon_row(&sim, w, h);
    assert!(horizon > 40.0 && horizon < 200.0, "horizon at row {horizon}");
    // Between the conifer on the left and the terrace on the right: ground and sky only.
    let top = horizon as u32 - 10;
    let rows = row_means(&img, 170..260, top..horizon as u32 + 12);
    assert_no_dark_band("eye height", &rows, top, 1.5);
    // The sky is lighter than the terrain in every channel, and the terrain grows lighter
    // towards the horizon as it fades into the haze.
    let (sky, ground) = (rows[0], rows[rows.len() - 1]);
    assert!((0..3).all(|c| sky[c] > ground[c] + 10.0), "sky {sky:?}, terrain {ground:?}");
}

#[test]
fn from_above_the_terrain_fades_into_the_sky_without_a_band() {
    // `grove aerial scene`'s default camera over a 204.8 m photograph (a 2048² pair at 0.1 m):
    // 71.7 m up, 122.9 m south of the centre, looking at it; the horizon lies just above the
    // top of a 960 × 540 image, and the terrain ends at the far plane about 60 rows below it.
    let (w, h) = (960, 540);
    let mut sim = study();
    let side = 204.8f32;
    sim.set_up().camera(Head {
        pose: Pose::looking_at(Vec3::new(0.0, 0.35 * side, 0.6 * side), Vec3::ZERO),
        fov_y: 60f32.to_radians(),
    });
    let img = render(&sim, w, h);
    let horizon = horizon_row(&sim, w, h);
    assert!(horizon < 0.0 && horizon > -10.0, "horizon at row {horizon}");
    // The colour of the sky at the horizon straight ahead (north), from the study's camera.
    let eye = study();
    let eye_img = render(&eye, 480, 270);
    let eye_horizon = horizon_row(&eye, 480, 270) as u32;
    let sky = row_means(&eye_img, 170..260, eye_horizon - 4..eye_horizon - 2)[0];

    let cols = w / 2 - 60..w / 2 + 60;
    let rows = row_means(&img, cols.clone(), 0..200);
    // The top rows are the sky's colour at the horizon, not a band of another colour.
    for (y, r) in rows.iter().enumerate().take(30) {
        assert!(
            (0..3).all(|c| (r[c] - sky[c]).abs() < 12.0),
            "row {y} is {r:.0?}, not the sky's colour at the horizon {sky:.0?}"
        );
    }
    // From the terrain at the bottom of the stretch up to the top, no band: the terrain fades
    // into the sky.
    assert_no_dark_band("from above", &rows, 0, 4.0);
    // And it does fade: the terrain 200 rows down is darker than the haze at the top.
    assert!((0..3).all(|c| rows[0][c] > rows[199][c] + 10.0), "top {:?}, 200 rows down {:?}", rows[0], rows[199]);
}
