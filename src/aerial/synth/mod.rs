//! A synthetic summer and winter aerial pair of a park of our own trees, with its truth.
//!
//! There is no public registered summer/winter pair, so grove makes one. A park of side
//! `size · gsd` metres is laid out from one seeded RNG: trees of our four species (broadleaf,
//! birch and shrub are deciduous, conifer is evergreen) placed by dart throwing so crowns
//! barely touch, a lawn, a building with a green (sedum) roof, and a car park. It is then
//! photographed straight down (orthographic) twice, see [`shade`]: in summer every crown is in
//! leaf; in winter the deciduous crowns are bare branches over leaf litter, the conifers keep
//! their needles, the lawn has browned, the roof is grey and the green cars are gone. The two
//! flights differ in sun elevation, exposure and white balance.
//!
//! Every texel is a pure function of the layout and its position, so the images are the same
//! on any thread count. They are rendered in bands of rows and streamed to PNG, so memory stays
//! bounded for any size.

pub mod shade;

use std::path::Path;

use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use serde::Serialize;

use super::raster::{png_stream, write_atomic};
use super::AerialError;
pub use shade::{Flight, Season};

/// The smallest and largest image side `synth` makes, texels.
pub const SIZE_RANGE: (u32, u32) = (16, 65_536);

/// A tree species of the synthetic park (our catalogue's species).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Species {
    /// A large deciduous tree.
    Broadleaf,
    /// A deciduous tree with white bark.
    Birch,
    /// A small deciduous bush.
    Shrub,
    /// An evergreen tree.
    Conifer,
}

impl Species {
    /// Whether the species loses its leaves in winter.
    pub fn deciduous(self) -> bool {
        self != Species::Conifer
    }

    /// The catalogue's species name.
    pub fn name(self) -> &'static str {
        match self {
            Species::Broadleaf => "broadleaf",
            Species::Birch => "birch",
            Species::Shrub => "shrub",
            Species::Conifer => "conifer",
        }
    }

    /// Crown radius range (metres) and top height range (metres).
    fn ranges(self) -> ((f64, f64), (f64, f64)) {
        match self {
            Species::Broadleaf => ((2.4, 4.0), (10.0, 16.0)),
            Species::Birch => ((1.3, 2.2), (8.0, 13.0)),
            Species::Shrub => ((0.8, 1.4), (1.0, 2.2)),
            Species::Conifer => ((1.6, 2.8), (9.0, 15.0)),
        }
    }
}

/// One tree of the park, in metres from the image's top-left corner (x east, y south).
#[derive(Clone, Debug, PartialEq)]
pub struct Tree {
    /// Species.
    pub species: Species,
    /// Trunk position, metres east of the left edge.
    pub x: f64,
    /// Trunk position, metres south of the top edge.
    pub y: f64,
    /// Crown radius, metres.
    pub radius: f64,
    /// Height of the crown's top above the ground, metres.
    pub height: f64,
    /// Per-tree colour factor, about 0.85..1.15.
    pub tint: f64,
    /// Per-tree seed of the texture and the branch pattern.
    pub seed: u32,
}

/// The kind of a green distractor (an object that is green in summer and not a tree).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum DistractorKind {
    /// A lawn that browns in winter (an ellipse inside its box).
    Lawn,
    /// A green (sedum) roof, grey in winter.
    Roof,
    /// A green car, parked only during the summer flight.
    Car,
}

/// An axis-aligned box, metres.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rect {
    /// Left, metres.
    pub x0: f64,
    /// Top, metres.
    pub y0: f64,
    /// Right, metres.
    pub x1: f64,
    /// Bottom, metres.
    pub y1: f64,
}

impl Rect {
    /// Whether a point lies inside.
    pub fn contains(&self, x: f64, y: f64) -> bool {
        x >= self.x0 && x < self.x1 && y >= self.y0 && y < self.y1
    }

    fn grown(&self, by: f64) -> Rect {
        Rect { x0: self.x0 - by, y0: self.y0 - by, x1: self.x1 + by, y1: self.y1 + by }
    }
}

/// A green distractor.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Distractor {
    /// What it is.
    pub kind: DistractorKind,
    /// Its box, metres.
    pub rect: Rect,
}

/// The laid-out park.
#[derive(Clone, Debug)]
pub struct Park {
    /// Image side, texels.
    pub size: u32,
    /// Ground sample distance, metres per texel.
    pub gsd: f64,
    /// The seed it was made from.
    pub seed: u64,
    /// The trees.
    pub trees: Vec<Tree>,
    /// The green distractors (summer).
    pub distractors: Vec<Distractor>,
    /// The car park's box, metres (asphalt), if the park is big enough for one.
    pub car_park: Option<Rect>,
    /// Cars of other colours, parked during the winter flight.
    pub winter_cars: Vec<Rect>,
}

/// One row of `truth.csv`.
#[derive(Clone, Debug, PartialEq, Serialize, serde::Deserialize)]
pub struct TruthRow {
    /// 1-based id.
    pub id: u32,
    /// Species name.
    pub species: String,
    /// `deciduous` or `evergreen`.
    pub kind: String,
    /// Trunk (crown centre), pixels from the left edge.
    pub x_px: f64,
    /// Trunk (crown centre), pixels from the top edge.
    pub y_px: f64,
    /// Crown radius, pixels.
    pub radius_px: f64,
    /// Crown centre, metres east of the left edge.
    pub x_m: f64,
    /// Crown centre, metres south of the top edge.
    pub y_m: f64,
    /// Crown radius, metres.
    pub radius_m: f64,
    /// Top height, metres.
    pub height_m: f64,
}

/// One row of `distractors.csv`: a green distractor's box in pixels.
#[derive(Clone, Debug, PartialEq, Serialize, serde::Deserialize)]
pub struct DistractorRow {
    /// `lawn`, `roof` or `car`.
    pub kind: String,
    /// Left edge, pixels.
    pub x0_px: f64,
    /// Top edge, pixels.
    pub y0_px: f64,
    /// Right edge, pixels.
    pub x1_px: f64,
    /// Bottom edge, pixels.
    pub y1_px: f64,
}

impl Park {
    /// Lays out a park of `size × size` texels at `gsd` metres per texel from `seed`.
    pub fn layout(size: u32, gsd: f64, seed: u64) -> Park {
        let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0xA5E1_7A11);
        let side = size as f64 * gsd;
        let mut distractors = Vec::new();
        let at = |fx: f64, fy: f64, w: f64, h: f64| Rect { x0: fx * side, y0: fy * side, x1: fx * side + w, y1: fy * side + h };
        // The lawn and the roof scale with the park; the car park holds cars of a real size.
        distractors.push(Distractor { kind: DistractorKind::Lawn, rect: at(0.08, 0.62, 0.15 * side, 0.11 * side) });
        distractors.push(Distractor { kind: DistractorKind::Roof, rect: at(0.66, 0.1, 0.12 * side, 0.08 * side) });
        let (car_w, car_h, slot) = (1.9, 4.5, 2.6);
        let mut car_park = None;
        let mut winter_cars = Vec::new();
        let slots = ((0.22 * side) / slot).floor() as usize;
        if slots >= 4 {
            let lot = at(0.7, 0.8, slots as f64 * slot, 6.0);
            car_park = Some(lot);
            // A few green cars in summer, two cars of other colours in winter, in other slots.
            let greens = 2 + (rng.random_range(0..3usize)).min(slots - 2);
            let mut order: Vec<usize> = (0..slots).collect();
            for i in (1..order.len()).rev() {
                order.swap(i, rng.random_range(0..=i));
            }
            let car = |s: usize| Rect { x0: lot.x0 + s as f64 * slot + 0.35, y0: lot.y0 + 0.75, x1: lot.x0 + s as f64 * slot + 0.35 + car_w, y1: lot.y0 + 0.75 + car_h };
            for &s in &order[..greens] {
                distractors.push(Distractor { kind: DistractorKind::Car, rect: car(s) });
            }
            for &s in &order[greens..(greens + 2).min(slots)] {
                winter_cars.push(car(s));
            }
        }
        let mut blocked: Vec<Rect> = distractors.iter().map(|d| d.rect).collect();
        blocked.extend(car_park);
        // Dart throwing: one tree per 150 m² is the goal; crowns may overlap by 5 % of their radii.
        let goal = (side * side / 150.0).ceil() as usize;
        let cell = 8.0;
        let cells = (side / cell).ceil().max(1.0) as usize;
        let mut grid: Vec<Vec<u32>> = vec![Vec::new(); cells * cells];
        let mut trees: Vec<Tree> = Vec::new();
        for _ in 0..goal * 30 {
            if trees.len() >= goal {
                break;
            }
            let species = match rng.random_range(0..100u32) {
                0..30 => Species::Broadleaf,
                30..55 => Species::Birch,
                55..75 => Species::Shrub,
                _ => Species::Conifer,
            };
            let ((r0, r1), (h0, h1)) = species.ranges();
            let radius = rng.random_range(r0..r1);
            let height = rng.random_range(h0..h1);
            let tint = rng.random_range(0.85..1.15);
            let seed = rng.random::<u32>();
            if side <= 2.0 * radius {
                continue;
            }
            let x = rng.random_range(radius..side - radius);
            let y = rng.random_range(radius..side - radius);
            if blocked.iter().any(|b| b.grown(radius).contains(x, y)) {
                continue;
            }
            let (cx, cy) = (((x / cell) as usize).min(cells - 1), ((y / cell) as usize).min(cells - 1));
            let clear = (cy.saturating_sub(1)..=(cy + 1).min(cells - 1)).all(|gy| {
                (cx.saturating_sub(1)..=(cx + 1).min(cells - 1)).all(|gx| {
                    grid[gy * cells + gx].iter().all(|&i| {
                        let t = &trees[i as usize];
                        ((t.x - x).powi(2) + (t.y - y).powi(2)).sqrt() >= 0.95 * (t.radius + radius)
                    })
                })
            });
            if clear {
                grid[cy * cells + cx].push(trees.len() as u32);
                trees.push(Tree { species, x, y, radius, height, tint, seed });
            }
        }
        Park { size, gsd, seed, trees, distractors, car_park, winter_cars }
    }

    /// The truth rows: every tree with its kind, centre and crown radius.
    pub fn truth(&self) -> Vec<TruthRow> {
        self.trees
            .iter()
            .enumerate()
            .map(|(i, t)| TruthRow {
                id: i as u32 + 1,
                species: t.species.name().into(),
                kind: if t.species.deciduous() { "deciduous" } else { "evergreen" }.into(),
                x_px: t.x / self.gsd,
                y_px: t.y / self.gsd,
                radius_px: t.radius / self.gsd,
                x_m: t.x,
                y_m: t.y,
                radius_m: t.radius,
                height_m: t.height,
            })
            .collect()
    }

    /// The distractor rows, boxes in pixels.
    pub fn distractor_rows(&self) -> Vec<DistractorRow> {
        let kind = |k: DistractorKind| match k {
            DistractorKind::Lawn => "lawn",
            DistractorKind::Roof => "roof",
            DistractorKind::Car => "car",
        };
        self.distractors
            .iter()
            .map(|d| DistractorRow {
                kind: kind(d.kind).into(),
                x0_px: d.rect.x0 / self.gsd,
                y0_px: d.rect.y0 / self.gsd,
                x1_px: d.rect.x1 / self.gsd,
                y1_px: d.rect.y1 / self.gsd,
            })
            .collect()
    }

    /// Renders rows `y0..y1` of one flight into `out` (RGB, `(y1 − y0) · size · 3` bytes),
    /// in parallel over rows.
    pub fn render_rows(&self, scene: &shade::Shader, y0: u32, out: &mut [u8]) {
        let w = self.size as usize;
        out.par_chunks_mut(w * 3).enumerate().for_each(|(dy, row)| {
            let y = y0 as usize + dy;
            for (x, t) in row.chunks_exact_mut(3).enumerate() {
                t.copy_from_slice(&scene.texel(x as u32, y as u32));
            }
        });
    }

    /// Renders a whole flight into memory (for small parks and tests).
    pub fn render(&self, season: Season) -> super::raster::RgbImage {
        let shader = shade::Shader::new(self, Flight::of(season));
        let mut data = vec![0u8; self.size as usize * self.size as usize * 3];
        self.render_rows(&shader, 0, &mut data);
        super::raster::RgbImage { width: self.size, height: self.size, data }
    }
}

/// Writes `summer.png`, `winter.png`, `truth.csv` and `distractors.csv` into `dir` (the caller has
/// checked that they may be written), rendering in bands of rows; `progress` gets the number of
/// rows finished so far.
pub fn write_pair(park: &Park, dir: &Path, progress: &dyn Fn(u64)) -> Result<(), AerialError> {
    let summer = shade::Shader::new(park, Flight::of(Season::Summer));
    let winter = shade::Shader::new(park, Flight::of(Season::Winter));
    let n = park.size;
    let band = 64u32;
    let (sp, wp) = (dir.join("summer.png"), dir.join("winter.png"));
    let (ps, pw) = (sp.display().to_string(), wp.display().to_string());
    write_atomic(&sp, |ws| {
        write_atomic(&wp, |ww| {
            png_stream(ws, n, n, 3, |s_rows| {
                png_stream(ww, n, n, 3, |w_rows| {
                    let mut buf_s = vec![0u8; band as usize * n as usize * 3];
                    let mut buf_w = buf_s.clone();
                    let mut y = 0;
                    while y < n {
                        let rows = band.min(n - y) as usize;
                        let len = rows * n as usize * 3;
                        rayon::join(|| park.render_rows(&summer, y, &mut buf_s[..len]), || park.render_rows(&winter, y, &mut buf_w[..len]));
                        s_rows.write_all(&buf_s[..len]).map_err(|e| AerialError::Io(e).named(&ps))?;
                        w_rows.write_all(&buf_w[..len]).map_err(|e| AerialError::Io(e).named(&pw))?;
                        y += rows as u32;
                        progress(y as u64);
                    }
                    Ok(())
                })
                .map_err(|e| e.named(&pw))
            })
            .map_err(|e| e.named(&ps))
        })
    })?;
    write_csv(&dir.join("truth.csv"), &park.truth())?;
    write_csv(&dir.join("distractors.csv"), &park.distractor_rows())
}

fn write_csv<T: Serialize>(path: &Path, rows: &[T]) -> Result<(), AerialError> {
    write_atomic(path, |w| {
        let mut csv = crate::csv_cells::Writer::from_writer(w);
        for r in rows {
            csv.serialize(r).map_err(|e| AerialError::Csv(e).named(path.display()))?;
        }
        csv.flush().map_err(|e| AerialError::Io(e).named(path.display()))
    })
}
