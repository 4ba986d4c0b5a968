//! Issue #39's bound on every cheaper way of drawing the park: the park as `grove render` draws it
//! now (full quality: grass, water, shadows, 480 × 270) stays within a mean absolute error of
//! 4/255 per channel of the full-quality image of 2026-11-27, drawn by the renderer of commit
//! 26c04b3, before the trees were culled per pass and the shell layers walked in one fragment
//! (`tests/snapshots/park-full-quality-2026-11-27.png`). That image is fixed: it is the
//! reference, not a golden to regenerate. The bound is on cheaper ways of drawing, not on the
//! look changed on purpose since: the park is drawn here without the blade lawn's edge fade
//! (`--no-blade-fade`), which came later and is tested by its own (`grass::edges`' unit tests,
//! the grass goldens), and with the species bank as it was that day
//! (`tests/fixtures/banks/species-2026-11-27`, the same files as commit 98062fd's
//! `assets/banks/species`): the species' leaves and needles were changed on purpose later (#61)
//! and are tested by `species::`.
//!
//! Renders with the `grove` binary on whatever adapter wgpu finds (lavapipe in CI).

use crate::common;

use common::{grove, root};

#[test]
fn the_park_stays_within_4_of_255_per_channel_of_the_full_quality_image_of_2026_11_27() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("park.png");
    let scene = dir.path().join("park.ron");
    std::fs::write(&scene, park_on_the_bank_of_2026_11_27(dir.path())).unwrap();
    let run = grove(&[
        "render",
        "--scene",
        scene.to_str().unwrap(),
        "--width",
        "480",
        "--height",
        "270",
        "--no-blade-fade",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(run.status.success(), "grove render failed: {}", String::from_utf8_lossy(&run.stderr));
    let now = image::open(&out).unwrap().to_rgb8();
    let reference = image::open(root().join("tests/snapshots/park-full-quality-2026-11-27.png")).unwrap().to_rgb8();
    assert_eq!(now.dimensions(), reference.dimensions());
    let mut sums = [0u64; 3];
    for (p, q) in now.pixels().zip(reference.pixels()) {
        for c in 0..3 {
            sums[c] += u64::from(p[c].abs_diff(q[c]));
        }
    }
    let n = u64::from(now.width() * now.height()) as f64;
    let mean = sums.map(|s| s as f64 / n);
    assert!(mean.iter().all(|&m| m <= 4.0), "mean absolute error per channel {mean:.3?} over 4/255");
}

/// assets/scenes/park.ron with its bank the fixture of 2026-11-27, written to be read from `dir`
/// (a scene names its banks by paths relative to itself).
fn park_on_the_bank_of_2026_11_27(dir: &std::path::Path) -> String {
    let park = std::fs::read_to_string(root().join("assets/scenes/park.ron")).unwrap();
    let dir = dir.canonicalize().unwrap();
    let bank = root().canonicalize().unwrap().join("tests/fixtures/banks/species-2026-11-27");
    let up = "../".repeat(dir.components().count() - 1);
    let relative = format!("{up}{}", bank.strip_prefix("/").unwrap().display());
    let shipped = "banks: [\"../banks/species\"]";
    assert!(park.contains(shipped), "park.ron no longer names its bank as {shipped}");
    park.replace(shipped, &format!("banks: [\"{relative}\"]"))
}
