//! How the species look through the renderer (issue #61, docs/species.md): the shrub at 3 m
//! (stems at its base, no leaf brighter than the sunlit ground, gaps at its edge), light on the
//! crowns at every sun elevation of the study's day (no crown darker at the top than at the
//! bottom), and, with `UPDATE_SNAPSHOTS=1`, the sheet of every species from 3, 10 and 30 m,
//! `docs/species-distances.png`. Each draws the model of level of detail 1, which the species
//! bank plants.

use grove::models::ModelData;
use image::{Rgba, RgbaImage};

use crate::shared_gpu::{self, LOCK};
use crate::species_render::{generate, luma, root, update, view_lit};

/// The model with its bark drawn plain red.
fn red_bark(data: &ModelData) -> ModelData {
    let mut red = data.clone();
    for m in red.materials.iter_mut().filter(|m| m.alpha_cutoff.is_none()) {
        m.albedo = None;
        m.base_color = glam::Vec4::new(1.0, 0.0, 0.0, 1.0);
    }
    red
}

/// The model with its leaves alone drawn magenta (no green at all) and its bark clipped away
/// whole (kept, so that the leaves keep their places in the model).
fn magenta_leaves(data: &ModelData) -> ModelData {
    let mut leaves = data.clone();
    for m in leaves.materials.iter_mut() {
        if m.alpha_cutoff.is_none() {
            m.alpha_cutoff = Some(0.5);
            m.base_color = glam::Vec4::ZERO;
        } else {
            m.base_color = glam::Vec4::new(4.0, 0.0, 4.0, 1.0);
        }
    }
    leaves
}

/// Where a render of [`magenta_leaves`] shows a leaf: red and blue well above green, and not
/// the stage's pixel.
fn leaf_mask(foliage: &RgbaImage, stage: &RgbaImage) -> Vec<bool> {
    foliage
        .pixels()
        .zip(stage.pixels())
        .map(|(p, q)| p != q && p.0[0] > p.0[1].saturating_add(12) && p.0[2] > p.0[1].saturating_add(6))
        .collect()
}

fn is_red(p: &Rgba<u8>) -> bool {
    p.0[0] > 60 && u16::from(p.0[0]) > 2 * u16::from(p.0[1]) + 20 && u16::from(p.0[0]) > 2 * u16::from(p.0[2]) + 20
}

/// The shrub from 3 m at eye height, 480×360, every leaf drawn: its stems show at its base (with
/// the bark drawn red, red pixels are at least 3 % of its silhouette's lowest fifth), no more
/// than 0.5 % of its leaf pixels are brighter than the sunlit ground (the brightest pixel of the
/// stage's lowest fifth), and its edge is broken (in its silhouette's outer fifth on either side,
/// row by row, at least 25 % of the pixels are not the shrub's).
#[test]
fn the_shrub_at_3_m_shows_its_stems_and_gaps_and_no_bright_leaf() {
    let (w, h) = (480u32, 360u32);
    let dir = tempfile::tempdir().unwrap();
    let (_, lod1) = generate("shrub", dir.path());
    let _guard = LOCK.lock().unwrap_or_else(|e| e.into_inner());
    let img = view_lit(&lod1, 3.0, true, (w, h), 0.0, 40.0);
    let stage = view_lit(&lod1, 3.0, false, (w, h), 0.0, 40.0);
    let stems = view_lit(&red_bark(&lod1), 3.0, true, (w, h), 0.0, 40.0);
    let foliage = view_lit(&magenta_leaves(&lod1), 3.0, true, (w, h), 0.0, 40.0);
    let leaves = leaf_mask(&foliage, &stage);
    let red: Vec<bool> = stems.pixels().map(is_red).collect();
    let shrub: Vec<bool> = leaves.iter().zip(&red).map(|(a, b)| *a || *b).collect();
    let mut ground: Vec<f32> =
        stage.enumerate_pixels().filter(|(_, y, _)| *y >= h * 4 / 5).map(|(_, _, p)| luma(p)).collect();
    ground.sort_by(f32::total_cmp);
    let sunlit = ground[ground.len() - 1];
    let leaf_px = leaves.iter().filter(|&&m| m).count();
    let bright = img.pixels().zip(&leaves).filter(|(p, m)| **m && luma(p) > sunlit).count();
    let rows: Vec<(usize, usize, usize)> = (0..h as usize)
        .filter_map(|y| {
            let row = &shrub[y * w as usize..(y + 1) * w as usize];
            Some((y, row.iter().position(|&m| m)?, row.iter().rposition(|&m| m)?))
        })
        .collect();
    let (top, bottom) = (rows[0].0, rows[rows.len() - 1].0);
    let base = bottom - (bottom - top) / 5;
    let (mut base_px, mut base_red) = (0usize, 0usize);
    let (mut edge, mut gaps) = (0usize, 0usize);
    for &(y, a, b) in &rows {
        let row = y * w as usize;
        if y >= base {
            base_px += shrub[row + a..=row + b].iter().filter(|&&m| m).count();
            base_red += red[row + a..=row + b].iter().filter(|&&m| m).count();
        }
        let fifth = (b - a) / 5;
        for x in (a..=a + fifth).chain(b - fifth..=b) {
            edge += 1;
            gaps += usize::from(!shrub[row + x]);
        }
    }
    let (stems_share, gap_share) = (base_red as f64 / base_px.max(1) as f64, gaps as f64 / edge.max(1) as f64);
    eprintln!(
        "shrub at 3 m: {leaf_px} leaf px, sunlit ground {sunlit:.0}, {bright} brighter ({:.2} %); stems {:.1} % of the lowest fifth; gaps {:.1} % of the outer fifth",
        bright as f64 * 100.0 / leaf_px.max(1) as f64,
        stems_share * 100.0,
        gap_share * 100.0
    );
    if update() {
        img.save(root().join("docs/species-shrub-3m.png")).unwrap();
    }
    assert!(leaf_px > 5_000, "the shrub should be seen at 3 m ({leaf_px} leaf px)");
    assert!(
        (bright as f64) <= 0.005 * leaf_px as f64,
        "{bright} of the shrub's {leaf_px} leaf px are brighter than the sunlit ground ({sunlit:.0})"
    );
    assert!(stems_share >= 0.03, "stems are {:.1} % of the lowest fifth of the shrub", stems_share * 100.0);
    assert!(gap_share >= 0.25, "gaps are {:.1} % of the shrub's outer fifth", gap_share * 100.0);
}

/// The sun's elevations over the study's day (21 June 2026 at Zurich, 47.38° N,
/// `assets/scenes/study.ron`): from just after sunrise to its noon height of about 66°.
const STUDY_DAY_ELEVATIONS: [f64; 5] = [8.0, 20.0, 35.0, 50.0, 66.0];

/// The mean luma of the leaf pixels of a crown in its top and bottom thirds (by the rows its
/// leaves cover).
fn top_and_bottom(img: &RgbaImage, leaves: &[bool]) -> (f32, f32) {
    let w = img.width() as usize;
    let rows: Vec<usize> =
        (0..img.height() as usize).filter(|y| leaves[y * w..(y + 1) * w].iter().any(|&m| m)).collect();
    let (top, bottom) = (rows[0], rows[rows.len() - 1]);
    let third = (bottom - top) / 3;
    let mean = |lo: usize, hi: usize| {
        let v: Vec<f32> = (lo..=hi)
            .flat_map(|y| (0..w).map(move |x| (x, y)))
            .filter(|&(x, y)| leaves[y * w + x])
            .map(|(x, y)| luma(img.get_pixel(x as u32, y as u32)))
            .collect();
        v.iter().sum::<f32>() / v.len().max(1) as f32
    };
    (mean(top, top + third), mean(bottom - third, bottom))
}

/// From eye height, far enough to see the whole tree, at each sun elevation of the study's day:
/// no crown is darker in its top third than in its bottom third.
#[test]
fn no_crown_is_darker_at_the_top_than_at_the_bottom_at_any_sun_elevation_of_the_study_day() {
    let (w, h) = (200u32, 260u32);
    let dir = tempfile::tempdir().unwrap();
    let mut failures = Vec::new();
    for species in ["oak", "birch", "beech", "scots_pine", "norway_spruce", "shrub"] {
        let (_, lod1) = generate(species, &dir.path().join(species));
        let distance = 1.5 * lod1.bounds.1.y;
        let _guard = LOCK.lock().unwrap_or_else(|e| e.into_inner());
        let leaves = leaf_mask(
            &view_lit(&magenta_leaves(&lod1), distance, true, (w, h), 0.0, 40.0),
            &view_lit(&lod1, distance, false, (w, h), 0.0, 40.0),
        );
        for elevation in STUDY_DAY_ELEVATIONS {
            let img = view_lit(&lod1, distance, true, (w, h), 0.0, elevation);
            let (top, bottom) = top_and_bottom(&img, &leaves);
            eprintln!(
                "{species} with the sun {elevation}° up: leaves' mean luma {top:.1} in the top third, {bottom:.1} in the bottom third"
            );
            if top < bottom {
                failures.push(format!("{species} at {elevation}°: top {top:.1} < bottom {bottom:.1}"));
            }
        }
    }
    assert!(failures.is_empty(), "crowns darker at the top: {failures:?}");
}

/// With `UPDATE_SNAPSHOTS=1`, writes `docs/species-distances.png`: every species (rows) from 3,
/// 10 and 30 m (columns) at eye height, 320×240 each, as the renderer draws it by default
/// (leaves simplified by distance); otherwise checks the committed sheet's layout.
#[test]
fn species_from_3_10_and_30_m() {
    let (w, h) = (320u32, 240u32);
    let species = ["oak", "birch", "beech", "scots_pine", "norway_spruce", "shrub"];
    let distances = [3.0f32, 10.0, 30.0];
    let path = root().join("docs/species-distances.png");
    if !update() {
        let sheet =
            image::open(&path).unwrap_or_else(|e| panic!("{}: {e}; write it with UPDATE_SNAPSHOTS=1", path.display()));
        assert_eq!((sheet.width(), sheet.height()), (w * distances.len() as u32, h * species.len() as u32));
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let mut sheet = RgbaImage::new(w * distances.len() as u32, h * species.len() as u32);
    let leaf_pixels = grove::render::RenderOptions::default().leaf_pixels;
    for (row, s) in species.iter().enumerate() {
        let (_, lod1) = generate(s, &dir.path().join(s));
        let _guard = LOCK.lock().unwrap_or_else(|e| e.into_inner());
        let _ = shared_gpu::shared_gpu("the species' distances");
        for (col, d) in distances.iter().enumerate() {
            let img = view_lit(&lod1, *d, true, (w, h), leaf_pixels, 40.0);
            image::imageops::replace(&mut sheet, &img, (col as u32 * w) as i64, (row as u32 * h) as i64);
        }
    }
    grove::atomic_write::write_via_temp(&path, |tmp| Ok(sheet.save(tmp)?)).unwrap();
}
