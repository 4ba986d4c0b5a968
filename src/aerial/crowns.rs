//! Crowns: the 8-connected components of a treetop mask, and the `crowns.csv` format.
//!
//! The mask is cut into runs (maximal horizontal stretches of set texels), found in parallel
//! per row. Two runs on neighbouring rows belong to one crown when they touch, diagonals
//! included; a union-find over the runs, in scan order with the smaller index as the root, joins
//! them. A crown's id is its rank in scan order of its first texel (top row first, then left),
//! so the result does not depend on the thread count.
//!
//! Per crown: the area in texels, the centroid (mean texel centre, in pixels from the image's
//! top-left corner) and the equivalent radius `sqrt(area / π)`, each also in metres from the
//! ground sample distance.

use std::path::Path;

use grove_systems::files::{self, Kind};

use super::AerialError;

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// One crown: a row of `crowns.csv`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Crown {
    /// 1-based id, in scan order of the crown's first texel.
    pub id: u32,
    /// Centroid, pixels from the left edge (texel centres at i + 0.5).
    pub x_px: f64,
    /// Centroid, pixels from the top edge.
    pub y_px: f64,
    /// Area, texels.
    pub area_px: u64,
    /// Equivalent radius `sqrt(area / π)`, pixels.
    pub radius_px: f64,
    /// Centroid, metres east of the left edge.
    pub x_m: f64,
    /// Centroid, metres south of the top edge.
    pub y_m: f64,
    /// Area, square metres.
    pub area_m2: f64,
    /// Equivalent radius, metres.
    pub radius_m: f64,
}

#[derive(Clone, Copy)]
struct Run {
    y: u32,
    x0: u32,
    /// One past the last texel.
    x1: u32,
}

fn row_runs(row: &[u8], y: u32) -> Vec<Run> {
    let mut runs = Vec::new();
    let mut x = 0;
    while x < row.len() {
        if row[x] != 0 {
            let x0 = x;
            while x < row.len() && row[x] != 0 {
                x += 1;
            }
            runs.push(Run { y, x0: x0 as u32, x1: x as u32 });
        } else {
            x += 1;
        }
    }
    runs
}

fn find(parent: &mut [u32], mut i: u32) -> u32 {
    while parent[i as usize] != i {
        let p = parent[i as usize];
        parent[i as usize] = parent[p as usize];
        i = p;
    }
    i
}

fn union(parent: &mut [u32], a: u32, b: u32) {
    let (ra, rb) = (find(parent, a), find(parent, b));
    if ra != rb {
        let (lo, hi) = if ra < rb { (ra, rb) } else { (rb, ra) };
        parent[hi as usize] = lo;
    }
}

/// The crowns of a mask (non-zero = treetop) of `width × height`, with `gsd` metres per pixel.
pub fn label_crowns(mask: &[u8], width: u32, height: u32, gsd: f64) -> Vec<Crown> {
    let w = width as usize;
    assert_eq!(mask.len(), w * height as usize, "mask size");
    if w == 0 {
        return Vec::new();
    }
    let per_row: Vec<Vec<Run>> = mask.par_chunks(w).enumerate().map(|(y, row)| row_runs(row, y as u32)).collect();
    let mut starts = Vec::with_capacity(per_row.len() + 1);
    let mut runs = Vec::new();
    for r in per_row {
        starts.push(runs.len());
        runs.extend(r);
    }
    starts.push(runs.len());
    let mut parent: Vec<u32> = (0..runs.len() as u32).collect();
    for y in 1..height as usize {
        let (prev, cur) = (starts[y - 1]..starts[y], starts[y]..starts[y + 1]);
        let mut i = prev.start;
        for j in cur {
            let b = runs[j];
            // Skip runs of the row above that end left of b's reach.
            while i < prev.end && runs[i].x1 < b.x0 {
                i += 1;
            }
            let mut k = i;
            // 8-connected: [a.x0, a.x1) touches [b.x0, b.x1) when a.x0 <= b.x1 and b.x0 <= a.x1.
            while k < prev.end && runs[k].x0 <= b.x1 {
                union(&mut parent, k as u32, j as u32);
                k += 1;
            }
        }
    }
    // Accumulate per root; roots are the first run of their component in scan order.
    let mut index_of_root = vec![u32::MAX; runs.len()];
    let mut sums: Vec<(u64, f64, f64)> = Vec::new();
    for i in 0..runs.len() {
        let root = find(&mut parent, i as u32) as usize;
        if index_of_root[root] == u32::MAX {
            index_of_root[root] = sums.len() as u32;
            sums.push((0, 0.0, 0.0));
        }
        let s = &mut sums[index_of_root[root] as usize];
        let Run { y, x0, x1 } = runs[i];
        let len = (x1 - x0) as u64;
        s.0 += len;
        // Sum of the column indices x0..x1 and of the row index over the run, exact in f64.
        s.1 += (x0 as u64 + x1 as u64 - 1) as f64 * len as f64 / 2.0;
        s.2 += y as f64 * len as f64;
    }
    sums.iter()
        .enumerate()
        .map(|(i, &(area, sx, sy))| {
            let x_px = sx / area as f64 + 0.5;
            let y_px = sy / area as f64 + 0.5;
            let radius_px = (area as f64 / std::f64::consts::PI).sqrt();
            Crown {
                id: i as u32 + 1,
                x_px,
                y_px,
                area_px: area,
                radius_px,
                x_m: x_px * gsd,
                y_m: y_px * gsd,
                area_m2: area as f64 * gsd * gsd,
                radius_m: radius_px * gsd,
            }
        })
        .collect()
}

/// Checks that every crown's numbers are finite: a table grove writes is one grove can read
/// back, so no non-finite number is ever written.
pub fn check_finite(crowns: &[Crown]) -> Result<(), AerialError> {
    match crowns.iter().find(|c| ![c.x_px, c.y_px, c.radius_px, c.x_m, c.y_m, c.area_m2, c.radius_m].iter().all(|v| v.is_finite())) {
        Some(c) => Err(AerialError::CrownNotFinite(c.id)),
        None => Ok(()),
    }
}

/// Writes `crowns.csv` (header and one row per crown) atomically.
pub fn write_csv(path: &Path, crowns: &[Crown]) -> Result<(), AerialError> {
    check_finite(crowns).map_err(|e| e.named(path.display()))?;
    super::raster::write_atomic(path, |w| {
        let mut csv = crate::csv_cells::Writer::from_writer(w);
        for c in crowns {
            csv.serialize(c).map_err(|e| AerialError::Csv(e).named(path.display()))?;
        }
        csv.flush().map_err(|e| AerialError::Io(e).named(path.display()))
    })
}

/// Reads `crowns.csv`, checking every number; errors name the file and the row.
pub fn read_csv(path: &Path) -> Result<Vec<Crown>, AerialError> {
    let name = path.display();
    let (file, _) = files::open(path, Kind::Table).map_err(AerialError::File)?;
    let mut rdr = csv::Reader::from_reader(std::io::BufReader::new(std::io::Read::take(file, Kind::Table.limit())));
    let mut out = Vec::new();
    for (i, row) in rdr.deserialize::<Crown>().enumerate() {
        let c = row.map_err(|e| AerialError::Row { row: i + 2, message: e.to_string().replace('\n', " ") }.named(&name))?;
        let nums = [c.x_px, c.y_px, c.radius_px, c.x_m, c.y_m, c.area_m2, c.radius_m];
        if nums.iter().any(|v| !v.is_finite() || *v < 0.0) {
            return Err(AerialError::BadRow(i + 2).named(&name));
        }
        out.push(c);
    }
    Ok(out)
}

/// `summary.json`, written by `grove aerial segment` beside `crowns.csv`: what was segmented
/// and how. `grove aerial scene` reads the image size and ground resolution from it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Summary {
    /// Image width, texels.
    pub width: u32,
    /// Image height, texels.
    pub height: u32,
    /// Ground sample distance, metres per texel.
    pub gsd_m: f64,
    /// Window side.
    pub k: u32,
    /// Summer green fraction threshold.
    pub s: f64,
    /// Winter not-green fraction threshold.
    pub w: f64,
    /// Whether both images were equalised.
    pub equalize: bool,
    /// Treetop texels in the mask.
    pub treetop_texels: u64,
    /// Crowns found.
    pub crowns: usize,
}

/// Reads the `summary.json` beside a `crowns.csv`.
pub fn read_summary(crowns_csv: &Path) -> Result<Summary, AerialError> {
    let path = crowns_csv.parent().unwrap_or(Path::new(".")).join("summary.json");
    let text = files::read_text(&path, Kind::Index).map_err(AerialError::NoSummary)?;
    let s: Summary = serde_json::from_str(&text).map_err(|e| AerialError::Json(e).named(path.display()))?;
    if s.width == 0 || s.height == 0 || !(s.gsd_m.is_finite() && s.gsd_m > 0.0) {
        return Err(AerialError::SummarySize.named(path.display()));
    }
    Ok(s)
}
