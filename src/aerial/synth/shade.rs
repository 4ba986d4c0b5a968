//! The synthetic photographs: what one texel of the park looks like from straight above.
//!
//! Frame: x east, y south (image axes), z up, metres. The sun's azimuth is clockwise from north
//! (−y), its elevation above the horizon. A texel's colour is `albedo · light · exposure ·
//! white balance + sensor noise`, where `light = ambient + sun · max(0, n · s)` for the surface
//! normal n and the unit vector s towards the sun.
//!
//! - Deciduous crowns in leaf are spheroid caps with a clumpy leaf texture (Perlin noise) and a
//!   slightly ragged outline; in winter they are bare: limbs radiating from the trunk and a
//!   random tangle of twigs, with the leaf litter below showing between them.
//! - Conifers are star-shaped cones of dark needles in both seasons.
//! - The ground is dry meadow and soil, patches of evergreen grass, and leaf litter under the
//!   deciduous trees. Trees cast elliptical crown shadows and trunk shadows away from the sun;
//!   a bare crown casts a dappled shadow.
//! - The distractors: a lawn (green in summer, brown in winter), a green roof (grey in winter),
//!   green cars parked in summer only.

use noise::{NoiseFn, Perlin};

use super::{DistractorKind, Park, Species, Tree};

/// Which flight.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Season {
    /// Trees in leaf.
    Summer,
    /// Deciduous trees bare.
    Winter,
}

/// The conditions of one flight.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Flight {
    /// The season.
    pub season: Season,
    /// Sun elevation above the horizon, degrees.
    pub sun_elevation_deg: f64,
    /// Sun azimuth, degrees clockwise from north.
    pub sun_azimuth_deg: f64,
    /// Exposure factor of the camera.
    pub exposure: f64,
    /// White balance gains (R, G, B) of the camera and film.
    pub white_balance: [f64; 3],
    /// Sky light, as a fraction of the albedo.
    pub ambient: f64,
    /// Direct sun light on a surface facing the sun.
    pub sun: f64,
}

impl Flight {
    /// The two flights of the synthetic pair: a high summer sun with a warm cast, and a low
    /// winter sun, a longer exposure and a slightly green cast (another camera and film).
    pub fn of(season: Season) -> Flight {
        match season {
            Season::Summer => Flight {
                season,
                sun_elevation_deg: 58.0,
                sun_azimuth_deg: 165.0,
                exposure: 1.0,
                white_balance: [1.06, 1.0, 0.92],
                ambient: 0.35,
                sun: 0.8,
            },
            Season::Winter => Flight {
                season,
                sun_elevation_deg: 19.0,
                sun_azimuth_deg: 175.0,
                exposure: 1.45,
                white_balance: [0.92, 1.08, 1.0],
                ambient: 0.3,
                sun: 0.8,
            },
        }
    }
}

/// Renders texels of one flight of a park.
pub struct Shader<'a> {
    park: &'a Park,
    flight: Flight,
    /// Unit vector towards the sun.
    to_sun: [f64; 3],
    /// Horizontal unit vector of the shadows (away from the sun).
    shadow_dir: [f64; 2],
    cell: f64,
    cells: usize,
    /// Per grid cell, the trees whose crown, litter or shadow may reach into it.
    grid: Vec<Vec<u32>>,
    perlin: Perlin,
}

const GRID_CELL_M: f64 = 4.0;

fn splitmix(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// A uniform number in [0, 1) from integers.
fn hash01(a: u64, b: u64, c: u64) -> f64 {
    let h = splitmix(splitmix(splitmix(a) ^ b) ^ c);
    (h >> 11) as f64 / (1u64 << 53) as f64
}

/// A uniform number in [0, 1) that is constant over `cell`-metre squares.
fn cell_noise(seed: u64, x: f64, y: f64, cell: f64) -> f64 {
    hash01(seed, (x / cell).floor() as i64 as u64, (y / cell).floor() as i64 as u64)
}

impl<'a> Shader<'a> {
    /// Prepares one flight of a park.
    pub fn new(park: &'a Park, flight: Flight) -> Shader<'a> {
        let (el, az) = (flight.sun_elevation_deg.to_radians(), flight.sun_azimuth_deg.to_radians());
        let to_sun = [az.sin() * el.cos(), -az.cos() * el.cos(), el.sin()];
        let shadow_dir = [-az.sin(), az.cos()];
        let side = park.size as f64 * park.gsd;
        let cells = (side / GRID_CELL_M).ceil().max(1.0) as usize;
        let mut grid = vec![Vec::new(); cells * cells];
        let mut shader = Shader {
            park,
            flight,
            to_sun,
            shadow_dir,
            cell: GRID_CELL_M,
            cells,
            grid: Vec::new(),
            perlin: Perlin::new(park.seed as u32),
        };
        for (i, t) in park.trees.iter().enumerate() {
            let (sx, sy, a, _) = shader.shadow(t);
            let reach = 1.25 * t.radius;
            let (x0, x1) = ((t.x - reach).min(sx - a), (t.x + reach).max(sx + a));
            let (y0, y1) = ((t.y - reach).min(sy - a), (t.y + reach).max(sy + a));
            let clampi = |v: f64| ((v / GRID_CELL_M).floor().max(0.0) as usize).min(cells - 1);
            for gy in clampi(y0)..=clampi(y1) {
                for gx in clampi(x0)..=clampi(x1) {
                    grid[gy * cells + gx].push(i as u32);
                }
            }
        }
        shader.grid = grid;
        shader
    }

    /// A tree's shadow: the ellipse centre (metres), its semi-axes along and across the shadow.
    fn shadow(&self, t: &Tree) -> (f64, f64, f64, f64) {
        let el = self.flight.sun_elevation_deg.to_radians();
        let mid = if t.species.deciduous() { (t.height - 0.9 * t.radius).max(0.5 * t.height) } else { 0.55 * t.height };
        let len = mid / el.tan();
        let along = (t.radius / el.sin()).min(4.0 * t.radius);
        (t.x + self.shadow_dir[0] * len, t.y + self.shadow_dir[1] * len, along, t.radius)
    }

    fn winter(&self) -> bool {
        self.flight.season == Season::Winter
    }

    fn light(&self, n: [f64; 3]) -> f64 {
        let d = n[0] * self.to_sun[0] + n[1] * self.to_sun[1] + n[2] * self.to_sun[2];
        self.flight.ambient + self.flight.sun * d.max(0.0)
    }

    /// The colour of texel (x, y).
    pub fn texel(&self, x: u32, y: u32) -> [u8; 3] {
        let gsd = self.park.gsd;
        let (px, py) = ((x as f64 + 0.5) * gsd, (y as f64 + 0.5) * gsd);
        let (albedo, light) = self.surface(px, py);
        let season = self.winter() as u64;
        let mut out = [0u8; 3];
        for c in 0..3 {
            // Shot noise: its spread grows with the square root of the signal (±4 levels at 100).
            let signal = albedo[c] * light * self.flight.exposure * self.flight.white_balance[c];
            let noise = (hash01(self.park.seed ^ (season << 40) ^ c as u64, x as u64, y as u64) - 0.5)
                * 0.8
                * signal.max(0.0).sqrt();
            let v = signal + noise;
            out[c] = v.round().clamp(0.0, 255.0) as u8;
        }
        out
    }

    /// Albedo (0..255 per channel) and light at a point, metres.
    fn surface(&self, px: f64, py: f64) -> ([f64; 3], f64) {
        let gx = ((px / self.cell) as usize).min(self.cells - 1);
        let gy = ((py / self.cell) as usize).min(self.cells - 1);
        let candidates = &self.grid[gy * self.cells + gx];
        let mut top: Option<(f64, [f64; 3], f64)> = None;
        let mut under_deciduous = false;
        for &i in candidates {
            let t = &self.park.trees[i as usize];
            let (qx, qy) = (px - t.x, py - t.y);
            let d = (qx * qx + qy * qy).sqrt();
            if t.species.deciduous() && d < 1.15 * t.radius {
                under_deciduous = true;
            }
            if d >= 1.1 * t.radius {
                continue;
            }
            if let Some((z, albedo, light)) = self.crown(t, qx, qy, d) {
                if top.is_none_or(|(best, _, _)| z > best) {
                    top = Some((z, albedo, light));
                }
            }
        }
        if let Some((_, albedo, light)) = top {
            return (albedo, light);
        }
        let albedo = self.ground(px, py, under_deciduous);
        // Shadows: the darkest one that covers the point.
        let mut lit = 1.0f64;
        for &i in candidates {
            let t = &self.park.trees[i as usize];
            lit = lit.min(self.shadow_at(t, px, py));
        }
        let flat = self.light([0.0, 0.0, 1.0]) - self.flight.ambient;
        // Where a tree blocks the sun it also hides part of the sky: a shadow keeps 60 % of the
        // sky light.
        (albedo, self.flight.ambient * (0.6 + 0.4 * lit) + flat * lit)
    }

    /// How much direct sun reaches a ground point past one tree: 1 lit, 0 in full shadow.
    fn shadow_at(&self, t: &Tree, px: f64, py: f64) -> f64 {
        let (sx, sy, a, b) = self.shadow(t);
        let (dx, dy) = (px - sx, py - sy);
        let u = dx * self.shadow_dir[0] + dy * self.shadow_dir[1];
        let v = -dx * self.shadow_dir[1] + dy * self.shadow_dir[0];
        let bare = self.winter() && t.species.deciduous();
        if (u / a).powi(2) + (v / b).powi(2) < 1.0 {
            if !bare {
                return 0.0;
            }
            // A bare crown lets most of the sun through, in flecks.
            return if cell_noise(t.seed as u64 ^ 0x51AD, px, py, 0.15) < 0.3 { 0.0 } else { 1.0 };
        }
        // The trunk's shadow: a band from the trunk to the crown's shadow.
        let (tx, ty) = (px - t.x, py - t.y);
        let along = tx * self.shadow_dir[0] + ty * self.shadow_dir[1];
        let across = (-tx * self.shadow_dir[1] + ty * self.shadow_dir[0]).abs();
        let reach = (sx - t.x) * self.shadow_dir[0] + (sy - t.y) * self.shadow_dir[1];
        let half_width = if t.species == Species::Shrub { 0.05 } else { 0.15 };
        if along > 0.0 && along < reach && across < half_width { 0.0 } else { 1.0 }
    }

    /// The crown of `t` at offset (qx, qy), distance d from the trunk: height, albedo and light,
    /// or `None` where the crown does not cover the point.
    fn crown(&self, t: &Tree, qx: f64, qy: f64, d: f64) -> Option<(f64, [f64; 3], f64)> {
        let r = t.radius;
        let off = (t.seed % 997) as f64 * 13.7;
        let theta = qy.atan2(qx);
        if t.species == Species::Conifer {
            // A star of branch tips: the outline swings between 0.8 r and r.
            let star = 0.8 + 0.2 * (7.0 * theta + off).cos().abs();
            if d >= r * star {
                return None;
            }
            let tt = d / r;
            let z = t.height - tt * 0.7 * t.height;
            let n = if d > 1e-6 { norm([qx / d * 0.9, qy / d * 0.9, 0.6]) } else { [0.0, 0.0, 1.0] };
            let f = self.perlin.get([(qx + off) / 0.25, (qy + off) / 0.25]);
            let base = if self.winter() { [33.0, 63.0, 42.0] } else { [35.0, 72.0, 42.0] };
            let shade = 1.0 + 0.2 * f;
            return Some((z, scale(base, t.tint * shade), self.light(n)));
        }
        let f = self.perlin.get([(qx + off) / 0.45, (qy + off) / 0.45]);
        let tt = d / r;
        if self.winter() {
            if tt >= 1.0 {
                return None;
            }
            return self.bare_crown(t, qx, qy, d, theta, off);
        }
        // Summer: a ragged outline and clumps of leaves.
        if d >= r * (1.0 + 0.08 * f) {
            return None;
        }
        let tt = tt.min(1.0);
        let cap = (1.0 - tt * tt).max(0.0).sqrt();
        let z = t.height - 0.8 * r * (1.0 - cap);
        let n = norm([qx / r, qy / r, cap + 0.15]);
        let base = match t.species {
            Species::Broadleaf => [55.0, 100.0, 35.0],
            Species::Birch => [88.0, 135.0, 50.0],
            _ => [65.0, 105.0, 40.0],
        };
        if f < -0.45 {
            // A gap between clumps: leaves deeper inside, in their own shade.
            return Some((z, scale(base, 0.55 * t.tint), self.flight.ambient + 0.3 * self.light(n)));
        }
        Some((z, scale(base, t.tint * (1.0 + 0.15 * f)), self.light(n)))
    }

    /// A leafless crown: limbs radiating from the trunk and a tangle of twigs.
    fn bare_crown(&self, t: &Tree, qx: f64, qy: f64, d: f64, theta: f64, off: f64) -> Option<(f64, [f64; 3], f64)> {
        let tt = d / t.radius;
        let limbs = 6 + (t.seed % 5) as usize;
        let mut on_limb = false;
        for i in 0..limbs {
            let a = std::f64::consts::TAU * i as f64 / limbs as f64 + off + 0.35 * (d * 0.9 + i as f64).sin();
            let mut delta = (theta - a).rem_euclid(std::f64::consts::TAU);
            if delta > std::f64::consts::PI {
                delta = std::f64::consts::TAU - delta;
            }
            if delta * d < 0.16 * (1.0 - 0.75 * tt) + 0.03 {
                on_limb = true;
                break;
            }
        }
        let density = if t.species == Species::Shrub { 0.6 } else { 0.35 + 0.25 * (1.0 - tt) };
        let twig = cell_noise(t.seed as u64, qx, qy, 0.1) < density;
        if !(on_limb || twig) {
            return None;
        }
        let (limb, twigs) = match t.species {
            Species::Birch => ([190.0, 185.0, 178.0], [120.0, 105.0, 95.0]),
            Species::Shrub => ([105.0, 82.0, 62.0], [105.0, 82.0, 62.0]),
            _ => ([100.0, 92.0, 84.0], [92.0, 80.0, 70.0]),
        };
        let z = t.height * (1.0 - 0.3 * tt);
        let albedo = if on_limb { limb } else { twigs };
        Some((z, scale(albedo, t.tint.sqrt()), self.light([0.0, 0.3, 0.95])))
    }

    /// The ground's albedo at a point.
    fn ground(&self, px: f64, py: f64, under_deciduous: bool) -> [f64; 3] {
        let winter = self.winter();
        let grain = 1.0 + 0.12 * self.perlin.get([px / 0.7 + 500.0, py / 0.7]);
        for dist in &self.park.distractors {
            let r = &dist.rect;
            match dist.kind {
                DistractorKind::Lawn => {
                    let (cx, cy) = ((r.x0 + r.x1) / 2.0, (r.y0 + r.y1) / 2.0);
                    let (ax, ay) = ((r.x1 - r.x0) / 2.0, (r.y1 - r.y0) / 2.0);
                    if ((px - cx) / ax).powi(2) + ((py - cy) / ay).powi(2) < 1.0 {
                        return scale(if winter { [125.0, 105.0, 70.0] } else { [80.0, 150.0, 55.0] }, grain);
                    }
                }
                DistractorKind::Roof => {
                    if r.contains(px, py) {
                        return scale(if winter { [125.0, 105.0, 95.0] } else { [85.0, 125.0, 60.0] }, grain);
                    }
                }
                DistractorKind::Car => {
                    if !winter && r.contains(px, py) {
                        return [45.0, 125.0, 65.0];
                    }
                }
            }
        }
        if let Some(lot) = self.park.car_park {
            if lot.contains(px, py) {
                if winter {
                    for (i, car) in self.park.winter_cars.iter().enumerate() {
                        if car.contains(px, py) {
                            return if i % 2 == 0 { [150.0, 40.0, 35.0] } else { [160.0, 160.0, 165.0] };
                        }
                    }
                }
                return scale([95.0, 92.0, 90.0], grain);
            }
        }
        let g = self.perlin.get([px / 9.0, py / 9.0 + 1000.0]);
        let albedo = if under_deciduous {
            if winter { [115.0, 88.0, 62.0] } else { [110.0, 90.0, 60.0] }
        } else if g > 0.2 {
            if winter { [70.0, 98.0, 55.0] } else { [85.0, 120.0, 55.0] }
        } else if winter {
            [120.0, 102.0, 82.0]
        } else {
            [150.0, 135.0, 95.0]
        };
        scale(albedo, grain)
    }
}

fn norm(v: [f64; 3]) -> [f64; 3] {
    let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    [v[0] / l, v[1] / l, v[2] / l]
}

fn scale(c: [f64; 3], f: f64) -> [f64; 3] {
    [c[0] * f, c[1] * f, c[2] * f]
}
