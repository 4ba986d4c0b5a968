//! Meshes of a generated tree at three levels of detail: swept tubes for the stems, one card per
//! leaf, the `_WIND` channels of `docs/assets.md` from the stem hierarchy (the trunk has no
//! distance from the axis, branches their distance, leaves also their distance from where they
//! hang; every stem of a first-level branch shares its phase), and vertex colours with each
//! leaf's colour variation and the crown's ambient occlusion.

use glam::{Vec2, Vec3, Vec4};

use super::atlas::{Atlas, Cell};
use super::preset::{LeafShape, Preset};
use super::stems::{Stem, Tree};
use crate::assetgen::geometry::{MeshData, tangent_frame};

/// The wood and the leaves of one level of detail.
#[derive(Clone, Debug, Default)]
pub struct Lod {
    /// Bark.
    pub wood: MeshData,
    /// Leaf cards.
    pub leaves: MeshData,
    /// Leaves kept.
    pub leaf_count: usize,
}

impl Lod {
    /// Triangles of wood and leaves.
    pub fn triangles(&self) -> usize {
        self.wood.triangles() + self.leaves.triangles()
    }
}

/// How finely the stems are swept.
#[derive(Clone, Copy, Debug)]
struct Detail {
    /// Sides are divided by this (at least 3).
    coarse: u32,
    /// Every `step`-th point of a stem becomes a ring (its last always does).
    step: usize,
    /// Stems deeper than this are left out.
    max_level: usize,
}

/// The shares of the full mesh's triangles the coarser levels of detail aim at.
pub const LOD_SHARES: [f32; 2] = [0.25, 0.05];

fn sides_of(level: usize, radius: f32) -> u32 {
    let base = match level {
        0 => 12,
        1 => 7,
        2 => 5,
        _ => 3,
    };
    (base + (radius * 40.0) as u32).min(20)
}

fn wind(p: Vec3, trunk: bool, attach: Option<Vec3>, phase: f32) -> Vec4 {
    let axis = if trunk { 0.0 } else { Vec2::new(p.x, p.z).length() };
    Vec4::new(p.y.max(0.0), axis, attach.map_or(0.0, |a| p.distance(a)), phase)
}

/// Sweeps a ring along a stem's points.
fn sweep(mesh: &mut MeshData, stem: &Stem, d: Detail, p: &Preset) {
    let n = stem.nodes.len();
    let mut picks: Vec<usize> = (0..n).step_by(d.step.max(1)).collect();
    if *picks.last().unwrap_or(&0) != n - 1 {
        picks.push(n - 1);
    }
    let sides = (sides_of(stem.level, stem.nodes[0].radius) / d.coarse).max(3);
    let trunk = stem.level == 0;
    let base = mesh.positions.len() as u32;
    let mut v = 0.0;
    for (j, &k) in picks.iter().enumerate() {
        let node = &stem.nodes[k];
        if j > 0 {
            v += node.pos.distance(stem.nodes[picks[j - 1]].pos);
        }
        let (bx, bz, axis) = (node.frame * Vec3::X, node.frame * Vec3::Z, node.frame * Vec3::Y);
        for i in 0..=sides {
            let a = i as f32 / sides as f32 * std::f32::consts::TAU;
            let (sa, ca) = a.sin_cos();
            let nrm = bx * ca + bz * sa;
            let lobe = if trunk && p.lobes > 0 {
                1.0 + p.lobe_depth * (p.lobes as f32 * a).sin() * (1.0 - k as f32 / n as f32)
            } else {
                1.0
            };
            let pos = node.pos + nrm * node.radius * lobe;
            let tan = -bx * sa + bz * ca;
            // The bark texture repeats about every 4 trunk radii around and along.
            let uv = Vec2::new(i as f32 / sides as f32, v / (stem.nodes[0].radius * 8.0).max(0.05));
            mesh.push(pos, nrm, tangent_frame(nrm, tan, axis), uv, wind(pos, trunk, None, stem.phase));
        }
    }
    let row = sides + 1;
    for j in 0..picks.len() as u32 - 1 {
        for i in 0..sides {
            let a = base + j * row + i;
            let (b, c) = (a + 1, a + row);
            mesh.indices.extend_from_slice(&[a, c, b, b, c, c + 1]);
        }
    }
}

fn wood(tree: &Tree, p: &Preset, d: Detail) -> MeshData {
    let mut mesh = MeshData::default();
    for stem in tree.stems.iter().filter(|s| s.level <= d.max_level) {
        sweep(&mut mesh, stem, d, p);
    }
    mesh
}

/// Which cells the leaf cards of a level of detail draw, and how large.
#[derive(Clone, Copy)]
enum Cards<'a> {
    /// Level 0: every leaf its own card of the atlas's first cell.
    Full(&'a Cell),
    /// Coarser levels: the share `keep` of the leaves, each a spray (the two alternately)
    /// centred where the middle of its card of level 0 (`card_len` long) was, grown by `grow`
    /// (1: the leaves keep their size).
    Sprays { sprays: &'a [Cell; 2], keep: f32, grow: f32, card_len: f32 },
}

/// The leaf cards of one level of detail (see [`Cards`]), with the count of cards.
fn leaves(tree: &Tree, cards: Cards) -> (MeshData, usize) {
    let mut mesh = MeshData::default();
    let centre = crown_centre(tree);
    let keep = match cards {
        Cards::Full(_) => 1.0,
        Cards::Sprays { keep, .. } => keep,
    };
    let mut acc = 0.0f32;
    let mut count = 0;
    for (i, leaf) in tree.leaves.iter().enumerate() {
        acc += keep;
        if acc < 1.0 {
            continue;
        }
        acc -= 1.0;
        count += 1;
        let (cell, size, shift) = match cards {
            Cards::Full(cell) => (cell, cell.size, 0.05 * cell.size.x),
            Cards::Sprays { sprays, grow, card_len, .. } => {
                // Alternate the two sprays by a hash of the leaf, not its order (a clump's
                // leaves are consecutive).
                let cell = &sprays[(crate::render::mix::mix(i as u64) & 1) as usize];
                let size = cell.size * grow;
                // The spray's middle where its leaf's middle was.
                (cell, size, 0.5 * (card_len - size.x))
            }
        };
        let (len, width) = (size.x, size.y);
        let side = leaf.dir.cross(leaf.normal).normalize_or(leaf.dir.any_orthonormal_vector());
        let base = leaf.attach + leaf.dir * shift;
        let tip = base + leaf.dir * len;
        let out = (base - centre).normalize_or(leaf.normal);
        let n = (leaf.normal * 0.6 + out).normalize_or(leaf.normal);
        let t = tangent_frame(n, side, -leaf.dir);
        let h = side * (0.5 * width);
        let corners = [
            (base - h, cell.at(0.0, 1.0)),
            (base + h, cell.at(1.0, 1.0)),
            (tip + h, cell.at(1.0, 0.0)),
            (tip - h, cell.at(0.0, 0.0)),
        ];
        let ids: Vec<u32> = corners
            .iter()
            .map(|&(q, uv)| mesh.push(q, n, t, uv, wind(q, false, Some(leaf.attach), leaf.phase)))
            .collect();
        mesh.indices.extend_from_slice(&[ids[0], ids[1], ids[2], ids[0], ids[2], ids[3]]);
        mesh.colors.extend(std::iter::repeat_n(Vec4::new(leaf.tint, leaf.depth, 0.0, 1.0), 4));
    }
    (mesh, count)
}

/// Fallen leaves under the crown (`litter`): flat cards of the atlas's litter cell just above
/// the ground, out to `litter` of the crown's radius, covering the disc about two and a half
/// times (cards `grow` times the litter cell's size, so fewer); no wind. Returns the cards.
fn litter(mesh: &mut MeshData, tree: &Tree, p: &Preset, cell: &Cell, crown_radius: f32, grow: f32) -> usize {
    if p.litter <= 0.0 {
        return 0;
    }
    let radius = p.litter * crown_radius;
    let card = (cell.size.x * grow).min(radius);
    let n = ((2.5 * radius * radius / (0.25 * card * card)).ceil() as usize).clamp(4, 400);
    let mut rng = crate::assetgen::geometry::Rng::new(0x11_77e2 ^ tree.leaves.len() as u64);
    for k in 0..n {
        let r = (radius - 0.35 * card).max(0.0) * rng.f().sqrt();
        let a = rng.range(0.0, std::f32::consts::TAU);
        let centre = Vec3::new(r * a.cos(), 0.01 + 0.004 * (k % 4) as f32, r * a.sin());
        let turn = rng.range(0.0, std::f32::consts::TAU);
        let (dir, side) = (Vec3::new(turn.cos(), 0.0, turn.sin()), Vec3::new(-turn.sin(), 0.0, turn.cos()));
        let t = tangent_frame(Vec3::Y, side, -dir);
        let (d, h) = (dir * 0.5 * card, side * 0.5 * card);
        let corners = [
            (centre - d - h, cell.at(0.0, 1.0)),
            (centre - d + h, cell.at(1.0, 1.0)),
            (centre + d + h, cell.at(1.0, 0.0)),
            (centre + d - h, cell.at(0.0, 0.0)),
        ];
        let ids: Vec<u32> = corners.iter().map(|&(q, uv)| mesh.push(q, Vec3::Y, t, uv, Vec4::ZERO)).collect();
        mesh.indices.extend_from_slice(&[ids[0], ids[1], ids[2], ids[0], ids[2], ids[3]]);
        // Darker towards the stems: the litter lies in the crown's shade.
        let shade = 0.35 + 0.3 * (r / radius.max(1e-3));
        mesh.colors.extend(std::iter::repeat_n(Vec4::new(shade, shade, shade, 1.0), 4));
    }
    n
}

fn crown_centre(tree: &Tree) -> Vec3 {
    if tree.leaves.is_empty() {
        return Vec3::new(0.0, tree.scale * 0.6, 0.0);
    }
    tree.leaves.iter().fold(Vec3::ZERO, |c, l| c + l.attach) / tree.leaves.len() as f32
}

/// The crown's outline: its horizontal radius in height bands, from the leaves.
struct Crown {
    lo: f32,
    hi: f32,
    radii: Vec<f32>,
}

const BANDS: usize = 24;

impl Crown {
    fn of(tree: &Tree) -> Crown {
        let (mut lo, mut hi) = (f32::MAX, f32::MIN);
        for l in &tree.leaves {
            lo = lo.min(l.attach.y);
            hi = hi.max(l.attach.y);
        }
        if lo >= hi {
            return Crown { lo: 0.0, hi: tree.scale.max(0.1), radii: vec![tree.scale * 0.3; BANDS] };
        }
        let mut radii = vec![0.0f32; BANDS];
        for l in &tree.leaves {
            let b = (((l.attach.y - lo) / (hi - lo)) * BANDS as f32).clamp(0.0, BANDS as f32 - 1.0) as usize;
            radii[b] = radii[b].max(Vec2::new(l.attach.x, l.attach.z).length());
        }
        // Smooth over neighbours so that an empty band does not read as the crown's edge.
        let smooth: Vec<f32> = (0..BANDS)
            .map(|b| radii[b.saturating_sub(1)..(b + 2).min(BANDS)].iter().copied().fold(0.0, f32::max).max(0.15))
            .collect();
        Crown { lo, hi, radii: smooth }
    }

    /// Ambient occlusion at `q` in 0..1 (1 unoccluded): darker deeper inside and lower in the crown.
    fn ao(&self, q: Vec3, strength: f32) -> f32 {
        let f = (q.y - self.lo) / (self.hi - self.lo);
        let b = (f * BANDS as f32).clamp(0.0, BANDS as f32 - 1.0) as usize;
        let rel = (Vec2::new(q.x, q.z).length() / self.radii[b]).clamp(0.0, 1.0);
        let mut occl = (1.0 - rel) * (0.55 + 0.45 * (1.0 - f.clamp(0.0, 1.0)));
        if f < 0.0 {
            occl *= 0.5;
        }
        1.0 - strength * occl
    }
}

/// Fills in the vertex colours: each leaf's tint (stored in red by `leaves`), the AO, and the
/// darkening of a clump's inside (its depth in the clump stored in green); on the wood the AO
/// times the bark's colour at its height over the texture's (`upper_bark_colour`).
fn shade(lod: &mut Lod, crown: &Crown, p: &Preset, height: f32) {
    let v = p.leaf_colour_v;
    for (q, c) in lod.leaves.positions.iter().zip(lod.leaves.colors.iter_mut()) {
        let t = c.x * 2.0 - 1.0;
        let ao = crown.ao(*q, p.ao) * (1.0 - CLUMP_AO * p.ao * (1.0 - c.y));
        // Variation in brightness and towards yellow-green.
        let tint = Vec3::new(1.0 + v * t * 1.2, 1.0 + v * t * 0.6, 1.0 - v * t * 0.4);
        *c = (tint * ao).min(Vec3::ONE).max(Vec3::ZERO).extend(1.0);
    }
    let texture = super::images::bark_texture_colour(p);
    lod.wood.colors = lod
        .wood
        .positions
        .iter()
        .map(|q| {
            let colour = match p.upper_bark_colour {
                Some(up) => {
                    let f = q.y / height.max(1e-3);
                    let t = ((f - (p.upper_bark_from - 0.2)) / 0.2).clamp(0.0, 1.0);
                    Vec3::from(p.bark_colour).lerp(Vec3::from(up), t * t * (3.0 - 2.0 * t))
                }
                None => Vec3::from(p.bark_colour),
            };
            // The ratio in linear light, as the renderer multiplies.
            let ratio = lin(colour) / lin(texture).max(Vec3::splat(1e-3));
            (ratio.min(Vec3::ONE) * crown.ao(*q, p.ao * 0.7)).extend(1.0)
        })
        .collect();
}

/// sRGB to linear, per channel.
fn lin(c: Vec3) -> Vec3 {
    let f = |x: f32| if x <= 0.04045 { x / 12.92 } else { ((x + 0.055) / 1.055).powf(2.4) };
    Vec3::new(f(c.x), f(c.y), f(c.z))
}

/// How much darker a clump's middle is than its outside, times the preset's `ao`.
const CLUMP_AO: f32 = 0.6;

/// The three levels of detail: every stem and leaf (each leaf card the atlas's first cell; a
/// spruce's, `Needles`, level 1's sprays),
/// then about 25 % and 5 % of its triangles: coarser tubes, fewer stem levels, and fewer leaf
/// cards, each a spray of the atlas; on level 1 the sprays' leaves keep their size (it keeps
/// `card_leaves / spray_leaves` of the cards), on level 2 they grow to keep the crown's area.
pub fn build(tree: &Tree, p: &Preset, atlas: &Atlas) -> [Lod; 3] {
    let crown = Crown::of(tree);
    let deepest = tree.stems.iter().map(|s| s.level).max().unwrap_or(0);
    let full_detail = Detail { coarse: 1, step: 1, max_level: deepest };
    let spray_keep = (atlas.card.leaves as f32 / atlas.sprays[0].leaves.max(1) as f32).min(1.0);
    // A spruce's needles stand all round its twigs: one card per shoot, its needles at their true
    // width (6 % of their length) in a single comb, leaves the space between the twigs empty and
    // reads bare from 10 m, so level 0 draws level 1's sprays of shoots (the needles at the same
    // length, combs at least 4 texels wide), with every stem.
    let full_cards = if p.leaf_shape == LeafShape::Needles {
        Cards::Sprays { sprays: &atlas.sprays, keep: spray_keep, grow: 1.0, card_len: atlas.card.size.x }
    } else {
        Cards::Full(&atlas.card)
    };
    let (l, n) = leaves(tree, full_cards);
    let mut full = Lod { wood: wood(tree, p, full_detail), leaves: l, leaf_count: n };
    let total = full.triangles() as f32;
    let mut out = [Lod::default(), Lod::default()];
    // The coarser levels count the leaves of level 0 as cards, whatever level 0 draws.
    let cards = tree.leaves.len();
    let sprays = (cards as f32 * spray_keep).round();
    for (k, share) in LOD_SHARES.iter().enumerate() {
        // Level 1: the sprays and at most as many triangles of wood (so the wood is at most
        // 60 % of a budget of 2.5 / 3 of the sprays' triangles); level 2: its share of level
        // 0's triangles, the wood at most 60 % of them.
        let target = if k == 0 { 2.0 * sprays / 0.6 } else { total * share };
        let mut d = Detail { coarse: 2 + 2 * k as u32, step: 2 + 2 * k, max_level: deepest };
        let mut w = wood(tree, p, d);
        // Leave out the finest stems until the wood takes at most 60 % of the budget.
        while w.triangles() as f32 > target * 0.6 && d.max_level > 0 {
            d.max_level -= 1;
            w = wood(tree, p, d);
        }
        let cards = if k == 0 {
            Cards::Sprays { sprays: &atlas.sprays, keep: spray_keep, grow: 1.0, card_len: atlas.card.size.x }
        } else {
            let room = ((target - w.triangles() as f32) / 2.0).max(0.0);
            let keep = if cards == 0 { 0.0 } else { (room / cards as f32).clamp(1e-3, spray_keep) };
            Cards::Sprays {
                sprays: &atlas.sprays,
                keep,
                grow: (spray_keep / keep).sqrt().min(4.0),
                card_len: atlas.card.size.x,
            }
        };
        let (l, n) = leaves(tree, cards);
        out[k] = Lod { wood: w, leaves: l, leaf_count: n };
    }
    let height = tree.scale;
    let radius = crown.radii.iter().copied().fold(0.0, f32::max);
    shade(&mut full, &crown, p, height);
    let [mut a, mut b] = out;
    shade(&mut a, &crown, p, height);
    shade(&mut b, &crown, p, height);
    // The coarsest level's litter in a quarter of the cards, twice as large.
    for (lod, grow) in [(&mut full, 1.0), (&mut a, 1.0), (&mut b, 2.0)] {
        litter(&mut lod.leaves, tree, p, &atlas.litter, radius, grow);
    }
    [full, a, b]
}
