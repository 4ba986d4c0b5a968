//! Quality of a treetop mask and its crowns against the truth of a synthetic pair.
//!
//! - **Mask**: the true treetop texels are those whose centre lies inside the crown disc of a
//!   deciduous tree of `truth.csv`. Precision, recall and F1 count texels.
//! - **Crown centres**: a detected crown matches a deciduous tree when its centroid lies within
//!   the tree's crown radius of the trunk; matching is one to one, closest pairs first. Crowns
//!   smaller than a minimum radius are not counted as detections.
//! - **Failure modes**: the fraction of conifer crown texels in the mask (they should be
//!   absent), and the mask texels inside each kind of green distractor's box.

use std::collections::BTreeMap;
use std::path::Path;

use serde::Serialize;

use super::AerialError;
use super::crowns::Crown;
use super::synth::{DistractorRow, TruthRow};

/// Counts and rates of a detection.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct Scores {
    /// True positives.
    pub tp: u64,
    /// False positives.
    pub fp: u64,
    /// False negatives.
    pub fn_: u64,
    /// tp / (tp + fp), 0 when nothing was detected.
    pub precision: f64,
    /// tp / (tp + fn), 0 when there is nothing to find.
    pub recall: f64,
    /// The harmonic mean of precision and recall, 0 when both are 0.
    pub f1: f64,
}

impl Scores {
    /// Rates from counts.
    pub fn new(tp: u64, fp: u64, fn_: u64) -> Scores {
        let ratio = |a: u64, b: u64| if b == 0 { 0.0 } else { a as f64 / b as f64 };
        let precision = ratio(tp, tp + fp);
        let recall = ratio(tp, tp + fn_);
        let f1 = if precision + recall == 0.0 { 0.0 } else { 2.0 * precision * recall / (precision + recall) };
        Scores { tp, fp, fn_, precision, recall, f1 }
    }
}

/// The quality of one mask.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Quality {
    /// Texel-wise scores against the deciduous crown discs.
    pub mask: Scores,
    /// The same, leaving out the texels inside the green distractors' boxes.
    pub mask_outside_distractors: Scores,
    /// Crown-centre scores against the deciduous trees.
    pub centres: Scores,
    /// Crowns counted as detections (radius at least the minimum).
    pub crowns: usize,
    /// Conifer crown texels.
    pub conifer_texels: u64,
    /// Conifer crown texels in the mask.
    pub conifer_texels_in_mask: u64,
    /// Detected crowns whose centroid lies within a conifer's crown radius.
    pub conifer_crowns: usize,
    /// Per distractor kind: (texels in its boxes, of which in the mask).
    pub distractors: BTreeMap<String, (u64, u64)>,
}

/// The truth of a synthetic pair: `truth.csv` and, if present, `distractors.csv`.
#[derive(Clone, Debug, Default)]
pub struct Truth {
    /// Every tree.
    pub trees: Vec<TruthRow>,
    /// The green distractors.
    pub distractors: Vec<DistractorRow>,
}

fn read_rows<T: serde::de::DeserializeOwned>(path: &Path) -> Result<Vec<T>, AerialError> {
    let name = path.display();
    let kind = grove_systems::files::Kind::Table;
    let (file, _) = grove_systems::files::open(path, kind).map_err(AerialError::File)?;
    let mut rdr = csv::Reader::from_reader(std::io::BufReader::new(std::io::Read::take(file, kind.limit())));
    rdr.deserialize::<T>()
        .enumerate()
        .map(|(i, r)| {
            r.map_err(|e| AerialError::Row { row: i + 2, message: e.to_string().replace('\n', " ") }.named(&name))
        })
        .collect()
}

impl Truth {
    /// Reads `truth.csv` and, when it exists, `distractors.csv` from a folder.
    pub fn read(dir: &Path) -> Result<Truth, AerialError> {
        let trees: Vec<TruthRow> = read_rows(&dir.join("truth.csv"))?;
        for t in &trees {
            if ![t.x_px, t.y_px, t.radius_px].iter().all(|v| v.is_finite()) || t.radius_px <= 0.0 {
                return Err(AerialError::BadTree(t.id).named(dir.join("truth.csv").display()));
            }
        }
        let dpath = dir.join("distractors.csv");
        let distractors = if dpath.exists() { read_rows(&dpath)? } else { Vec::new() };
        Ok(Truth { trees, distractors })
    }
}

/// Sets to `value` every texel whose centre lies inside the disc; `plane` is `width × height`.
pub fn fill_disc(plane: &mut [u8], width: u32, height: u32, cx: f64, cy: f64, r: f64, value: u8) {
    let x0 = (cx - r).floor().max(0.0) as u32;
    let y0 = (cy - r).floor().max(0.0) as u32;
    let x1 = ((cx + r).ceil().max(0.0) as u32).min(width);
    let y1 = ((cy + r).ceil().max(0.0) as u32).min(height);
    for y in y0..y1 {
        for x in x0..x1 {
            let (dx, dy) = (x as f64 + 0.5 - cx, y as f64 + 0.5 - cy);
            if dx * dx + dy * dy < r * r {
                plane[(y * width + x) as usize] = value;
            }
        }
    }
}

/// Scores a mask (non-zero = treetop) and its crowns against the truth.
pub fn evaluate(mask: &[u8], crowns: &[Crown], truth: &Truth, width: u32, height: u32, min_radius_px: f64) -> Quality {
    // 0 nothing, 1 deciduous, 2 conifer (conifers drawn last: they are the taller here).
    let mut classes = vec![0u8; mask.len()];
    for t in truth.trees.iter().filter(|t| t.kind == "deciduous") {
        fill_disc(&mut classes, width, height, t.x_px, t.y_px, t.radius_px, 1);
    }
    let mut conifers = vec![0u8; mask.len()];
    for t in truth.trees.iter().filter(|t| t.kind != "deciduous") {
        fill_disc(&mut conifers, width, height, t.x_px, t.y_px, t.radius_px, 1);
    }
    let mut boxed = vec![0u8; mask.len()];
    for d in &truth.distractors {
        let (x0, y0) = (d.x0_px.max(0.0).round() as u32, d.y0_px.max(0.0).round() as u32);
        let (x1, y1) = ((d.x1_px.max(0.0).round() as u32).min(width), (d.y1_px.max(0.0).round() as u32).min(height));
        for y in y0..y1 {
            boxed[(y * width + x0.min(x1)) as usize..(y * width + x1) as usize].fill(1);
        }
    }
    let (mut tp, mut fp, mut fn_, mut con, mut con_in) = (0u64, 0u64, 0u64, 0u64, 0u64);
    let mut outside = [0u64; 3];
    for (((&m, &c), &k), &b) in mask.iter().zip(&classes).zip(&conifers).zip(&boxed) {
        let set = m != 0;
        let slot = match (set, c == 1) {
            (true, true) => 0,
            (true, false) => 1,
            (false, true) => 2,
            _ => 3,
        };
        match slot {
            0 => tp += 1,
            1 => fp += 1,
            2 => fn_ += 1,
            _ => {}
        }
        if slot < 3 && b == 0 {
            outside[slot] += 1;
        }
        if k == 1 {
            con += 1;
            con_in += set as u64;
        }
    }
    let mut distractors: BTreeMap<String, (u64, u64)> = BTreeMap::new();
    for d in &truth.distractors {
        let e = distractors.entry(d.kind.clone()).or_default();
        let (x0, y0) = (d.x0_px.max(0.0).round() as u32, d.y0_px.max(0.0).round() as u32);
        let (x1, y1) = ((d.x1_px.max(0.0).round() as u32).min(width), (d.y1_px.max(0.0).round() as u32).min(height));
        for y in y0..y1 {
            for x in x0..x1 {
                e.0 += 1;
                e.1 += (mask[(y * width + x) as usize] != 0) as u64;
            }
        }
    }
    let detections: Vec<&Crown> = crowns.iter().filter(|c| c.radius_px >= min_radius_px).collect();
    let deciduous: Vec<&TruthRow> = truth.trees.iter().filter(|t| t.kind == "deciduous").collect();
    let matched = match_centres(&detections, &deciduous);
    let conifer_crowns = detections
        .iter()
        .filter(|c| {
            truth.trees.iter().any(|t| {
                t.kind != "deciduous"
                    && (c.x_px - t.x_px).powi(2) + (c.y_px - t.y_px).powi(2) <= t.radius_px * t.radius_px
            })
        })
        .count();
    Quality {
        mask: Scores::new(tp, fp, fn_),
        mask_outside_distractors: Scores::new(outside[0], outside[1], outside[2]),
        centres: Scores::new(matched, detections.len() as u64 - matched, deciduous.len() as u64 - matched),
        crowns: detections.len(),
        conifer_texels: con,
        conifer_texels_in_mask: con_in,
        conifer_crowns,
        distractors,
    }
}

/// One-to-one matching of crown centroids to trees within each tree's radius, closest first.
fn match_centres(crowns: &[&Crown], trees: &[&TruthRow]) -> u64 {
    let max_r = trees.iter().map(|t| t.radius_px).fold(1.0, f64::max);
    let cell = 2.0 * max_r;
    let mut grid: BTreeMap<(i64, i64), Vec<usize>> = BTreeMap::new();
    for (i, t) in trees.iter().enumerate() {
        grid.entry(((t.x_px / cell).floor() as i64, (t.y_px / cell).floor() as i64)).or_default().push(i);
    }
    let mut pairs: Vec<(f64, usize, usize)> = Vec::new();
    for (ci, c) in crowns.iter().enumerate() {
        let (gx, gy) = ((c.x_px / cell).floor() as i64, (c.y_px / cell).floor() as i64);
        for dy in -1..=1 {
            for dx in -1..=1 {
                for &ti in grid.get(&(gx + dx, gy + dy)).into_iter().flatten() {
                    let t = trees[ti];
                    let d = ((c.x_px - t.x_px).powi(2) + (c.y_px - t.y_px).powi(2)).sqrt();
                    if d <= t.radius_px {
                        pairs.push((d, ci, ti));
                    }
                }
            }
        }
    }
    pairs.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)).then(a.2.cmp(&b.2)));
    let (mut used_c, mut used_t) = (vec![false; crowns.len()], vec![false; trees.len()]);
    let mut n = 0;
    for (_, ci, ti) in pairs {
        if !used_c[ci] && !used_t[ti] {
            used_c[ci] = true;
            used_t[ti] = true;
            n += 1;
        }
    }
    n
}
