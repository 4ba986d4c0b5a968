//! The leaf texture of a species: an atlas of four square cells, each leaf (or needle, or pair of
//! needles) drawn at one scale and kept apart from its neighbours by at least a texel, so that
//! every leaf is an island of opaque texels whose extent, times the card's size, is the leaf's
//! length in the model.
//!
//! - cell 0, top left: the card of full detail (level 0): one leaf filling the cell (a broadleaf
//!   with `card_leaves: 1`), or a sprig or a shoot of `card_leaves` leaves or needles;
//! - cells 1 and 3, top right and bottom right: two sprays of `spray_leaves` leaves at the same
//!   size, for the cards of the coarser levels (each stands for `spray_leaves / card_leaves`
//!   cards of level 0), so that a coarser level draws fewer cards but not larger leaves;
//! - cell 2, bottom left: fallen leaves for the litter under a crown (`litter`).
//!
//! Pure functions of the preset: the same bytes on every run.

use glam::{Vec2, Vec3};
use image::{Rgba, RgbaImage};

use super::images::to8;
use super::preset::{LeafShape, Preset};
use crate::assetgen::geometry::Rng;

/// One cell of the atlas.
#[derive(Clone, Copy, Debug)]
pub struct Cell {
    /// The cell's texture rectangle: its corner of least u and v, and its corner of most.
    pub uv: [Vec2; 2],
    /// The leaves (or needles, or pairs of needles) drawn in it.
    pub leaves: usize,
    /// The card's length (along v) and width (along u), metres, at which its leaves have the
    /// preset's length.
    pub size: Vec2,
}

impl Cell {
    /// The atlas coordinates of `(u, v)` in 0..1 across the cell.
    pub fn at(&self, u: f32, v: f32) -> Vec2 {
        self.uv[0] + (self.uv[1] - self.uv[0]) * Vec2::new(u, v)
    }
}

/// A species' leaf atlas: the albedo with alpha, its height field (for the normal and specular
/// maps) and the cells.
pub struct Atlas {
    /// The albedo (sRGB) with alpha.
    pub image: RgbaImage,
    /// Height per texel, row by row.
    pub height: Vec<f32>,
    /// The atlas's side, texels.
    pub size: u32,
    /// The card of level 0.
    pub card: Cell,
    /// The two sprays of levels 1 and 2.
    pub sprays: [Cell; 2],
    /// The fallen leaves.
    pub litter: Cell,
}

/// A cell's side, texels: finer for needles, which are narrow.
pub fn cell_size(shape: LeafShape) -> u32 {
    match shape {
        LeafShape::Oval | LeafShape::Lobed => 256,
        LeafShape::Needles | LeafShape::NeedlePairs => 512,
    }
}

/// Texels kept clear along a cell's edges, so that mips do not bleed between cells.
const MARGIN: f32 = 6.0;

/// Whether `(u, v)` (u across 0..1, v from the tip 0 to the stalk 1) is on a broad leaf, and its
/// height there (midrib and veins raised).
fn broad_leaf_at(lobed: bool, u: f32, v: f32) -> Option<f32> {
    let across = (u - 0.5).abs() * 2.0;
    let pi = std::f32::consts::PI;
    if v > 0.8 && across < 0.08 {
        // The stalk, reaching into the blade's base.
        return Some(0.8);
    }
    if v > 0.9 {
        return None;
    }
    let t = v / 0.9;
    let mut profile = (pi * t).sin().powf(0.75);
    if lobed {
        profile *= 0.72 + 0.28 * (t * pi * 7.0).sin().abs();
    }
    if across >= profile * 0.96 {
        return None;
    }
    let mid = (1.0 - across / 0.05).max(0.0);
    let vein = if ((t * 8.0 + across * 2.5).fract() - 0.5).abs() < 0.07 { 0.35 } else { 0.0 };
    Some(0.3 + 0.5 * mid + vein + 0.15 * (1.0 - across / profile.max(1e-3)))
}

/// A needle from `base` along `dir` (unit) of length `len` and width `w`, texels: its height at
/// `q`, rounded across and thinning to a point over its last fifth.
fn needle_at(q: Vec2, base: Vec2, dir: Vec2, len: f32, w: f32) -> Option<f32> {
    let d = q - base;
    let a = d.dot(dir);
    if !(-0.5..=len).contains(&a) {
        return None;
    }
    let t = (a / len).clamp(0.0, 1.0);
    let r = 0.5 * w * (1.0 - ((t - 0.8) / 0.2).max(0.0) * 0.7);
    let off = (d - dir * a).length();
    (off <= r.max(0.5)).then(|| 0.55 + 0.4 * (1.0 - off / r.max(0.5)))
}

/// One leaf, needle or pair of needles placed in the atlas: its base, the unit direction from
/// base to tip, its length and width (texels) and its colour shift in -1..1.
#[derive(Clone, Copy, Debug)]
struct Stamp {
    base: Vec2,
    dir: Vec2,
    len: f32,
    width: f32,
    tint: f32,
}

impl Stamp {
    /// The height of the stamp at texel centre `q`, or `None` off it.
    fn at(&self, shape: LeafShape, q: Vec2) -> Option<f32> {
        match shape {
            LeafShape::Oval | LeafShape::Lobed => {
                let d = q - self.base;
                let side = Vec2::new(-self.dir.y, self.dir.x);
                let (a, c) = (d.dot(self.dir) / self.len, d.dot(side) / self.width);
                if !(0.0..=1.0).contains(&a) || c.abs() > 0.5 {
                    return None;
                }
                broad_leaf_at(shape == LeafShape::Lobed, 0.5 + c, 1.0 - a)
            }
            LeafShape::Needles => needle_at(q, self.base, self.dir, self.len, self.width),
            LeafShape::NeedlePairs => {
                // Two needles from one sheath, parting slightly.
                let (s, c) = PAIR_HALF_ANGLE.sin_cos();
                let a = Vec2::new(self.dir.x * c - self.dir.y * s, self.dir.x * s + self.dir.y * c);
                let b = Vec2::new(self.dir.x * c + self.dir.y * s, -self.dir.x * s + self.dir.y * c);
                needle_at(q, self.base, a, self.len, self.width)
                    .or_else(|| needle_at(q, self.base, b, self.len, self.width))
            }
        }
    }

    /// The texels the stamp may touch: a box around its axis, as wide as it and its pair's
    /// spread.
    fn bounds(&self) -> (Vec2, Vec2) {
        let tip = self.base + self.dir * self.len;
        let reach = Vec2::splat(0.5 * self.width + 0.15 * self.len + 1.5);
        (self.base.min(tip) - reach, self.base.max(tip) + reach)
    }
}

/// The atlas being drawn: texel owners (0 free, else the stamp's number), the texels a new
/// stamp may not touch (drawn ones and their neighbours) and what is drawn.
struct Canvas {
    size: u32,
    owner: Vec<u32>,
    blocked: Vec<bool>,
    height: Vec<f32>,
    tint: Vec<f32>,
    stamps: u32,
}

impl Canvas {
    fn new(size: u32) -> Canvas {
        let n = (size * size) as usize;
        Canvas { size, owner: vec![0; n], blocked: vec![false; n], height: vec![0.0; n], tint: vec![0.0; n], stamps: 0 }
    }

    /// The texels of `stamp` inside the rectangle `lo..hi` with their heights, or `None` when
    /// it leaves the rectangle or touches (by an edge or a corner) a texel already drawn.
    fn fit(&self, shape: LeafShape, stamp: &Stamp, lo: Vec2, hi: Vec2) -> Option<Vec<(usize, f32)>> {
        // A quick look along the axis first: most rejected places are rejected there.
        for k in 0..=8 {
            let q = stamp.base + stamp.dir * (stamp.len * k as f32 / 8.0);
            let (x, y) = (q.x as i64, q.y as i64);
            if x < 0
                || y < 0
                || x >= self.size as i64
                || y >= self.size as i64
                || self.blocked[(y * self.size as i64 + x) as usize]
            {
                return None;
            }
        }
        let (a, b) = stamp.bounds();
        let (x0, y0) = (a.x.floor().max(0.0) as i64, a.y.floor().max(0.0) as i64);
        let (x1, y1) = ((b.x.ceil() as i64).min(self.size as i64 - 1), (b.y.ceil() as i64).min(self.size as i64 - 1));
        let mut texels = Vec::new();
        for y in y0..=y1 {
            for x in x0..=x1 {
                let q = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
                let Some(h) = stamp.at(shape, q) else { continue };
                let i = (y * self.size as i64 + x) as usize;
                if q.x < lo.x || q.y < lo.y || q.x > hi.x || q.y > hi.y || self.blocked[i] {
                    return None;
                }
                texels.push((i, h));
            }
        }
        (!texels.is_empty()).then_some(texels)
    }

    /// Draws the texels of a stamp that fitted, and blocks them and their neighbours for the
    /// stamps to come.
    fn put(&mut self, texels: &[(usize, f32)], tint: f32) {
        self.stamps += 1;
        let size = self.size as i64;
        for &(i, h) in texels {
            self.owner[i] = self.stamps;
            self.height[i] = h;
            self.tint[i] = tint;
            let (x, y) = ((i as i64) % size, (i as i64) / size);
            for (nx, ny) in [
                (x - 1, y - 1),
                (x, y - 1),
                (x + 1, y - 1),
                (x - 1, y),
                (x, y),
                (x + 1, y),
                (x - 1, y + 1),
                (x, y + 1),
                (x + 1, y + 1),
            ] {
                if nx >= 0 && ny >= 0 && nx < size && ny < size {
                    self.blocked[(ny * size + nx) as usize] = true;
                }
            }
        }
    }

    /// Draws a stamp over whatever is there (the litter, whose leaves overlap).
    fn overdraw(&mut self, shape: LeafShape, stamp: &Stamp, lo: Vec2, hi: Vec2) {
        let (a, b) = stamp.bounds();
        let (a, b) = (a.max(lo), b.min(hi));
        self.stamps += 1;
        for y in a.y.floor() as i64..b.y.ceil() as i64 {
            for x in a.x.floor() as i64..b.x.ceil() as i64 {
                if let Some(h) = stamp.at(shape, Vec2::new(x as f32 + 0.5, y as f32 + 0.5)) {
                    let i = (y * self.size as i64 + x) as usize;
                    self.owner[i] = self.stamps;
                    self.height[i] = h;
                    self.tint[i] = stamp.tint;
                }
            }
        }
    }
}

/// A twig of a sprig or spray (not drawn: only where leaves grow from): from `a` to `b`, texels.
#[derive(Clone, Copy)]
struct Twig {
    a: Vec2,
    b: Vec2,
}

fn rotate(v: Vec2, angle: f32) -> Vec2 {
    let (s, c) = angle.sin_cos();
    Vec2::new(v.x * c - v.y * s, v.x * s + v.y * c)
}

/// The twigs of a cell whose corner is `o` and side `s` for leaves of `len` texels: a main axis
/// from the middle of the bottom edge upwards (ending `lead` texels short of the top, which the
/// needles at its end point on), and for a spray side twigs alternating up it, 50° to 60° from
/// it, two and a half leaf lengths apart on either side.
fn twigs(o: Vec2, s: f32, spray: bool, len: f32, lead: f32, rng: &mut Rng) -> Vec<Twig> {
    let base = o + Vec2::new(0.5 * s, s - MARGIN);
    let up = Vec2::new(0.0, -1.0);
    let main = Twig { a: base, b: base + rotate(up, rng.range(-0.05, 0.05)) * ((s - 2.0 * MARGIN) * 0.92 - lead) };
    let mut out = vec![main];
    if !spray {
        return out;
    }
    let along = main.b - main.a;
    let mut t = 0.1;
    let mut side = 1.0;
    while t < 0.85 {
        let angle = side * rng.range(50.0f32, 60.0).to_radians();
        let a = main.a + along * t;
        let reach = s * 0.42 * (1.0 - 0.45 * t) - lead * 0.5;
        if reach > 2.0 * len {
            out.push(Twig { a, b: a + rotate(along.normalize(), angle) * reach });
        }
        side = -side;
        t += 1.25 * len / angle.sin().abs() / along.length() * rng.range(0.95, 1.1);
    }
    out
}

/// Places up to `n` leaves (at random along the twigs) or needles (in combs) of about `len`
/// texels, and returns how many fitted.
#[allow(clippy::too_many_arguments)]
fn place(canvas: &mut Canvas, p: &Preset, twigs: &[Twig], o: Vec2, s: f32, n: usize, len: f32, rng: &mut Rng) -> usize {
    match p.leaf_shape {
        LeafShape::Oval | LeafShape::Lobed => grow(canvas, p, twigs, o, s, n, len, rng),
        LeafShape::Needles | LeafShape::NeedlePairs => comb(canvas, p, twigs, o, s, n, len, rng),
    }
}

/// Places up to `n` broad leaves of `len` texels (± 12 %) at random along `twigs` inside the cell
/// `o`, side `s`, each apart from the others, and returns how many fitted.
#[allow(clippy::too_many_arguments)]
fn grow(canvas: &mut Canvas, p: &Preset, twigs: &[Twig], o: Vec2, s: f32, n: usize, len: f32, rng: &mut Rng) -> usize {
    let (lo, hi) = (o + Vec2::splat(MARGIN), o + Vec2::splat(s - MARGIN));
    let total: f32 = twigs.iter().map(|t| t.a.distance(t.b)).sum();
    let mut placed = 0;
    let mut side = 1.0f32;
    for _ in 0..n * 80 {
        if placed == n {
            break;
        }
        // A point on the twigs (by length), and where on its twig.
        let mut pick = rng.range(0.0, total);
        let twig = twigs.iter().find(|t| {
            let l = t.a.distance(t.b);
            pick -= l;
            pick <= 0.0
        });
        let twig = *twig.unwrap_or(&twigs[twigs.len() - 1]);
        let t = rng.f();
        let along = (twig.b - twig.a).normalize_or(Vec2::NEG_Y);
        side = -side;
        // The leaf at a twig's very end points along it.
        let end = t > 0.97 && rng.f() < 0.5;
        let angle = if end { rng.range(-0.2, 0.2) } else { side * rng.range(35.0f32, 75.0).to_radians() };
        let dir = rotate(along, angle);
        let l = len * rng.range(0.88, 1.12);
        let stamp = Stamp {
            base: twig.a.lerp(twig.b, t) + dir * 1.5,
            dir,
            len: l,
            width: l * p.leaf_scale_x,
            tint: rng.range(-1.0, 1.0),
        };
        if let Some(texels) = canvas.fit(p.leaf_shape, &stamp, lo, hi) {
            canvas.put(&texels, stamp.tint);
            placed += 1;
        }
    }
    placed
}

/// Places up to `n` needles (or pairs) of `len` texels (± 10 %) in combs along `twigs` inside the
/// cell `o`, side `s`: to either side in turn, each next to the last with a texel between them,
/// leaning forward; a pine's (pairs) only on the last half of each twig, leaning the more the
/// nearer the twig's end, as a tuft. Returns how many fitted.
#[allow(clippy::too_many_arguments)]
fn comb(canvas: &mut Canvas, p: &Preset, twigs: &[Twig], o: Vec2, s: f32, n: usize, len: f32, rng: &mut Rng) -> usize {
    let (lo, hi) = (o + Vec2::splat(MARGIN), o + Vec2::splat(s - MARGIN));
    let pairs = p.leaf_shape == LeafShape::NeedlePairs;
    let width = (len * p.leaf_scale_x).max(MIN_NEEDLE_WIDTH);
    // A pair's two needles part by about a tenth of their length at the tips.
    let spread = if pairs { 2.0 * len * PAIR_HALF_ANGLE.sin() } else { 0.0 };
    let mut placed = 0;
    let all: f32 = twigs.iter().map(|t| t.a.distance(t.b)).sum();
    let mut due = 0.0;
    for twig in twigs {
        let along = (twig.b - twig.a).normalize_or(Vec2::NEG_Y);
        let total = twig.a.distance(twig.b);
        // Each twig its share of the needles by its length.
        due += n as f32 * total / all.max(1e-3);
        let n = (due.round() as usize).min(n);
        let from = if pairs { 0.35 } else { 0.0 };
        let mut t = from * total;
        let mut side = if rng.f() < 0.5 { 1.0 } else { -1.0 };
        while t <= total && placed < n {
            let rel = (t / total - from) / (1.0 - from);
            let angle_deg = if pairs { 75.0 - 55.0 * rel } else { 58.0 } + rng.range(-4.0, 4.0);
            let angle = angle_deg.to_radians();
            let dir = rotate(along, side * angle);
            let stamp = Stamp {
                base: twig.a + along * t + dir * 1.5,
                dir,
                len: len * rng.range(0.9, 1.1),
                width,
                tint: rng.range(-1.0, 1.0),
            };
            if let Some(texels) = canvas.fit(p.leaf_shape, &stamp, lo, hi) {
                canvas.put(&texels, stamp.tint);
                placed += 1;
            }
            side = -side;
            t += (width + spread + 1.5) / (2.0 * angle.sin()) * rng.range(0.95, 1.15);
        }
        // The twig's end: a few more pointing forward.
        for k in 0..3 {
            if placed >= n {
                break;
            }
            let dir = rotate(along, (k as f32 - 1.0) * 0.35 + rng.range(-0.05, 0.05));
            let stamp = Stamp {
                base: twig.b + dir * 1.5,
                dir,
                len: len * rng.range(0.9, 1.1),
                width,
                tint: rng.range(-1.0, 1.0),
            };
            if let Some(texels) = canvas.fit(p.leaf_shape, &stamp, lo, hi) {
                canvas.put(&texels, stamp.tint);
                placed += 1;
            }
        }
    }
    placed
}

/// Half the angle between a pine's two needles.
const PAIR_HALF_ANGLE: f32 = 0.015;

/// The narrowest needle, texels: four texels with one between neighbours keep a comb about
/// three quarters opaque, so that its mips (whose alpha the renderer raises by 15 % a level)
/// stay above the cutoff and a far conifer keeps its foliage.
const MIN_NEEDLE_WIDTH: f32 = 4.0;

/// The longest leaf, texels, tried for a sprig or spray of `n` broad leaves in a cell of side
/// `s`: their blades would cover about a third of the cell.
fn leaf_len(p: &Preset, n: usize, s: f32) -> f32 {
    s * (0.3 / (n.max(1) as f32 * 0.55 * p.leaf_scale_x)).sqrt().min(0.6)
}

/// Draws the cell `(cx, cy)` (side `s` texels) as a sprig (`spray` false: one twig) or a spray
/// of `n` leaves of about the greatest length at which at least 95 % of them fit (below the
/// length at which broad leaves would cover about a third of the cell, or needles half the
/// cell's side, found by bisection), or of the `known` length. `seed` makes the twigs and the
/// places.
fn sprig(
    canvas: &mut Canvas,
    p: &Preset,
    (cx, cy): (u32, u32),
    s: u32,
    spray: bool,
    n: usize,
    seed: u64,
    known: Option<f32>,
) -> Cell {
    let sf = s as f32;
    let o = Vec2::new((cx * s) as f32, (cy * s) as f32);
    let broad = matches!(p.leaf_shape, LeafShape::Oval | LeafShape::Lobed);
    let draw = |canvas: &mut Canvas, len: f32| {
        let mut rng = Rng::new(seed);
        let tw = twigs(o, sf, spray, len, if broad { 0.0 } else { 0.8 * len }, &mut rng);
        place(canvas, p, &tw, o, sf, n, len, &mut rng)
    };
    let fits = |len: f32| draw(&mut Canvas::new(canvas.size), len) as f32 >= 0.95 * n as f32;
    let len = match known {
        Some(len) => len,
        None => {
            // Halving the ratio between a length that fits and one that does not, six times.
            let (mut lo, mut hi) = (8.0f32, if broad { leaf_len(p, n, sf) } else { 0.5 * sf });
            if fits(hi) {
                hi
            } else {
                for _ in 0..6 {
                    let mid = (lo * hi).sqrt();
                    if fits(mid) {
                        lo = mid;
                    } else {
                        hi = mid;
                    }
                }
                lo
            }
        }
    };
    let k = draw(canvas, len);
    let uv = [Vec2::new(cx as f32 * 0.5, cy as f32 * 0.5), Vec2::new(cx as f32 * 0.5 + 0.5, cy as f32 * 0.5 + 0.5)];
    Cell { uv, leaves: k, size: Vec2::splat(p.leaf_scale * sf / len) }
}

/// Draws the atlas of preset `p`.
pub fn atlas(p: &Preset) -> Atlas {
    let s = cell_size(p.leaf_shape);
    let size = 2 * s;
    let mut canvas = Canvas::new(size);
    let seed = 0x5eed_1eaf ^ p.leaf_shape as u64;
    let sf = s as f32;
    let cell = |cx: u32, cy: u32| {
        [Vec2::new(cx as f32 * 0.5, cy as f32 * 0.5), Vec2::new(cx as f32 * 0.5 + 0.5, cy as f32 * 0.5 + 0.5)]
    };
    let broad = matches!(p.leaf_shape, LeafShape::Oval | LeafShape::Lobed);
    // Cell 0: one leaf filling the cell, or a sprig or shoot.
    let card = if broad && p.card_leaves == 1 {
        let stamp = Stamp { base: Vec2::new(0.5 * sf, sf), dir: Vec2::NEG_Y, len: sf, width: sf, tint: 0.0 };
        let texels = canvas.fit(p.leaf_shape, &stamp, Vec2::ZERO, Vec2::splat(sf)).unwrap_or_default();
        canvas.put(&texels, 0.0);
        Cell { uv: cell(0, 0), leaves: 1, size: Vec2::new(p.leaf_scale, p.leaf_scale * p.leaf_scale_x) }
    } else {
        sprig(&mut canvas, p, (0, 0), s, false, p.card_leaves as usize, seed, None)
    };
    // Cells 1 and 3: the sprays.
    let first = sprig(&mut canvas, p, (1, 0), s, true, p.spray_leaves as usize, seed ^ 1, None);
    // The second spray's leaves as long as the first's.
    let second = sprig(
        &mut canvas,
        p,
        (1, 1),
        s,
        true,
        p.spray_leaves as usize,
        seed ^ 2,
        Some(p.leaf_scale * sf / first.size.x),
    );
    let sprays = [first, second];
    let mut rng = Rng::new(seed ^ 3);
    // Cell 2: fallen leaves, overlapping, within a disc.
    let o = Vec2::new(0.0, sf);
    let (lo, hi) = (o + Vec2::splat(MARGIN), o + Vec2::splat(sf - MARGIN));
    let litter_len = if broad { sf * 0.16 } else { sf * 0.08 };
    let mut litter = 0;
    for _ in 0..if p.litter <= 0.0 {
        0
    } else if broad {
        90
    } else {
        500
    } {
        let r = (0.5 * sf - MARGIN - litter_len) * rng.f().sqrt();
        let at = o + Vec2::splat(0.5 * sf) + rotate(Vec2::X, rng.range(0.0, std::f32::consts::TAU)) * r;
        let dir = rotate(Vec2::X, rng.range(0.0, std::f32::consts::TAU));
        let l = litter_len * rng.range(0.8, 1.2);
        let width = if broad { l * p.leaf_scale_x } else { 2.0 };
        canvas.overdraw(
            p.leaf_shape,
            &Stamp { base: at - dir * 0.5 * l, dir, len: l, width, tint: rng.range(-1.0, 1.0) },
            lo,
            hi,
        );
        litter += 1;
    }
    let litter_first = canvas.stamps - litter as u32;
    let litter = Cell { uv: cell(0, 1), leaves: litter, size: Vec2::splat(p.leaf_scale * sf / litter_len) };
    let image = paint(p, &canvas, litter_first);
    Atlas { image, height: canvas.height, size, card, sprays, litter }
}

/// The albedo: each leaf the preset's colour, shaded by its height and shifted by its tint; the
/// litter's leaves brown; off the leaves the leaf colour at alpha 0 (so that filtering does not
/// darken the edges).
fn paint(p: &Preset, canvas: &Canvas, litter_first: u32) -> RgbaImage {
    let col = Vec3::from(p.leaf_colour);
    let brown = Vec3::new(0.27, 0.21, 0.14);
    RgbaImage::from_fn(canvas.size, canvas.size, |x, y| {
        let i = (y * canvas.size + x) as usize;
        if canvas.owner[i] == 0 {
            return Rgba([to8(col.x), to8(col.y), to8(col.z), 0]);
        }
        let (h, t) = (canvas.height[i], canvas.tint[i]);
        let c = if canvas.owner[i] > litter_first {
            brown * (0.7 + 0.3 * h) * (1.0 + 0.3 * t) * Vec3::new(1.0, 1.0 + 0.05 * t, 1.0 + 0.1 * t)
        } else {
            col * (0.85 + 0.3 * h) * Vec3::new(1.0 + 0.08 * t, 1.0 + 0.05 * t, 1.0 - 0.04 * t)
        };
        Rgba([to8(c.x), to8(c.y), to8(c.z), 255])
    })
}

#[cfg(test)]
#[path = "atlas_tests.rs"]
mod tests;
