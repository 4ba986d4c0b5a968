//! The four species: each builds a skeleton (wood limbs and foliage clusters) from a seeded RNG,
//! and then either real leaves (mesh models) or crossed cards (billboard models) around the
//! clusters.

use glam::{Vec3, Vec3Swizzles};

use super::geometry::{Limb, MeshData, Rng, card, leaf, tube};

/// The species the generator knows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Species {
    /// A round-crowned deciduous tree.
    Broadleaf,
    /// A tall cone of whorled branches.
    Conifer,
    /// A slender white-barked tree with a narrow, drooping crown.
    Birch,
    /// A low, many-stemmed bush.
    Shrub,
}

impl Species {
    /// All species in catalogue order.
    pub const ALL: [Species; 4] = [Species::Broadleaf, Species::Conifer, Species::Birch, Species::Shrub];

    /// The name used in file names and the catalogue.
    pub fn name(self) -> &'static str {
        match self {
            Species::Broadleaf => "broadleaf",
            Species::Conifer => "conifer",
            Species::Birch => "birch",
            Species::Shrub => "shrub",
        }
    }

    fn seed(self) -> u64 {
        match self {
            Species::Broadleaf => 0x6272_6f61,
            Species::Conifer => 0x636f_6e69,
            Species::Birch => 0x6269_7263,
            Species::Shrub => 0x7368_7275,
        }
    }
}

/// A place where foliage grows.
#[derive(Clone, Copy, Debug)]
pub struct Cluster {
    /// Centre of the foliage.
    pub centre: Vec3,
    /// The point on the branch it hangs from.
    pub attach: Vec3,
    /// The branch's phase, 0..1.
    pub phase: f32,
    /// Radius of the cluster, metres.
    pub radius: f32,
    /// The direction of the branch at the cluster (used by conifer needles and cards).
    pub along: Vec3,
}

/// Wood limbs with their tessellation, and foliage clusters.
pub struct Skeleton {
    /// (limb, sides, rings, droop) for the mesh and billboard variants.
    pub limbs: Vec<(Limb, u32, u32, f32)>,
    /// Foliage clusters.
    pub clusters: Vec<Cluster>,
    /// Centre of the crown, for foliage normals.
    pub crown_centre: Vec3,
}

fn golden(i: usize) -> f32 {
    i as f32 * 2.399_963
}

/// Builds the skeleton of a species. `cheap` lowers the tessellation for billboard models.
pub fn skeleton(species: Species, cheap: bool) -> Skeleton {
    let mut rng = Rng::new(species.seed());
    let mut limbs = Vec::new();
    let mut clusters = Vec::new();
    let (ts, bs, tw) = if cheap { (6, 4, 3) } else { (8, 5, 4) };
    let mut add = |limb: Limb, sides: u32, rings: u32, droop: f32| limbs.push((limb, sides, rings, droop));
    let crown_centre;
    match species {
        Species::Broadleaf => {
            crown_centre = Vec3::new(0.0, 4.9, 0.0);
            add(
                Limb {
                    start: Vec3::new(0.0, -0.05, 0.0),
                    end: Vec3::new(0.0, 3.2, 0.0),
                    r0: 0.24,
                    r1: 0.16,
                    phase: 0.0,
                    trunk: true,
                },
                ts,
                if cheap { 1 } else { 3 },
                0.0,
            );
            add(
                Limb {
                    start: Vec3::new(0.0, 3.2, 0.0),
                    end: Vec3::new(0.05, 5.6, -0.05),
                    r0: 0.16,
                    r1: 0.06,
                    phase: 0.0,
                    trunk: true,
                },
                ts,
                if cheap { 1 } else { 2 },
                0.0,
            );
            for i in 0..6 {
                let a = golden(i) + rng.range(-0.2, 0.2);
                let y = 2.7 + 0.3 * i as f32;
                let dir = Vec3::new(a.cos() * 0.85, rng.range(0.55, 0.8), a.sin() * 0.85).normalize();
                let len = rng.range(2.0, 2.5);
                let start = Vec3::new(0.0, y, 0.0);
                let end = start + dir * len;
                let phase = rng.f();
                add(Limb { start, end, r0: 0.09, r1: 0.035, phase, trunk: false }, bs, 2, 0.0);
                for k in 0..2 {
                    let s = 0.55 + 0.25 * k as f32;
                    let from = start + dir * len * s;
                    let side = Vec3::new(-dir.z, 0.0, dir.x) * if k == 0 { 1.0 } else { -1.0 };
                    let sdir = (dir + side * 0.9 + Vec3::Y * 0.3).normalize();
                    let slen = rng.range(0.8, 1.1);
                    let to = from + sdir * slen;
                    let sphase = rng.f();
                    add(Limb { start: from, end: to, r0: 0.035, r1: 0.015, phase: sphase, trunk: false }, tw, 1, 0.0);
                    clusters.push(Cluster { centre: to, attach: from, phase: sphase, radius: 0.8, along: sdir });
                }
                clusters.push(Cluster {
                    centre: end,
                    attach: start + dir * len * 0.7,
                    phase,
                    radius: 0.85,
                    along: dir,
                });
            }
            clusters.push(Cluster {
                centre: Vec3::new(0.0, 6.3, 0.0),
                attach: Vec3::new(0.0, 5.6, 0.0),
                phase: 0.5,
                radius: 0.9,
                along: Vec3::Y,
            });
        }
        Species::Conifer => {
            crown_centre = Vec3::new(0.0, 4.5, 0.0);
            add(
                Limb {
                    start: Vec3::new(0.0, -0.05, 0.0),
                    end: Vec3::new(0.0, 8.7, 0.0),
                    r0: 0.2,
                    r1: 0.025,
                    phase: 0.0,
                    trunk: true,
                },
                ts,
                if cheap { 2 } else { 6 },
                0.0,
            );
            let mut i = 0;
            let mut y = 1.3;
            while y < 8.4 {
                let per = if cheap { 4 } else { 5 };
                for k in 0..per {
                    let a = golden(i) + k as f32 * std::f32::consts::TAU / per as f32;
                    let len = 0.25 + 1.5 * (8.7 - y) / 7.4;
                    let dir = Vec3::new(a.cos(), rng.range(-0.25, -0.05), a.sin()).normalize();
                    let start = Vec3::new(0.0, y, 0.0);
                    let end = start + dir * len;
                    let phase = rng.f();
                    add(Limb { start, end, r0: 0.035, r1: 0.01, phase, trunk: false }, tw, 1, 0.08 * len);
                    for s in [0.45f32, 0.8] {
                        let c = start + dir * len * s;
                        clusters.push(Cluster {
                            centre: c,
                            attach: start + dir * len * (s - 0.2),
                            phase,
                            radius: 0.35 * len.max(0.5),
                            along: dir,
                        });
                    }
                }
                i += 1;
                y += 0.55;
            }
            clusters.push(Cluster {
                centre: Vec3::new(0.0, 8.65, 0.0),
                attach: Vec3::new(0.0, 8.3, 0.0),
                phase: 0.3,
                radius: 0.3,
                along: Vec3::Y,
            });
        }
        Species::Birch => {
            crown_centre = Vec3::new(0.0, 5.6, 0.0);
            let pts = [
                Vec3::new(0.0, -0.05, 0.0),
                Vec3::new(0.08, 3.0, 0.0),
                Vec3::new(0.02, 5.6, 0.08),
                Vec3::new(-0.03, 7.7, 0.0),
            ];
            let radii = [0.14, 0.1, 0.06, 0.02];
            for s in 0..3 {
                add(
                    Limb { start: pts[s], end: pts[s + 1], r0: radii[s], r1: radii[s + 1], phase: 0.0, trunk: true },
                    ts,
                    if cheap { 1 } else { 2 },
                    0.0,
                );
            }
            for i in 0..14 {
                let a = golden(i);
                let y = 2.8 + 4.4 * i as f32 / 13.0;
                // A narrow ovoid crown: longest branches a third of the way up the crown.
                let u = (y - 2.8) / 4.9;
                let len = 0.35 + 1.05 * (std::f32::consts::PI * (u * 0.85 + 0.15)).sin();
                let dir = Vec3::new(a.cos() * 0.7, 0.7, a.sin() * 0.7).normalize();
                let start = Vec3::new(0.05, y, 0.03);
                let end = start + dir * len;
                let phase = rng.f();
                add(Limb { start, end, r0: 0.03, r1: 0.01, phase, trunk: false }, tw, 1, 0.0);
                // Drooping twigs hanging from the branch end.
                let droop_end = end + Vec3::new(dir.x * 0.3, -0.7 * len, dir.z * 0.3);
                add(Limb { start: end, end: droop_end, r0: 0.01, r1: 0.005, phase, trunk: false }, 3, 1, 0.0);
                clusters.push(Cluster {
                    centre: end.lerp(droop_end, 0.5),
                    attach: end,
                    phase,
                    radius: 0.45,
                    along: (droop_end - end).normalize(),
                });
                clusters.push(Cluster {
                    centre: start.lerp(end, 0.55),
                    attach: start,
                    phase,
                    radius: 0.35,
                    along: dir,
                });
            }
            clusters.push(Cluster {
                centre: Vec3::new(0.0, 7.6, 0.0),
                attach: Vec3::new(0.0, 7.2, 0.0),
                phase: 0.7,
                radius: 0.35,
                along: Vec3::Y,
            });
        }
        Species::Shrub => {
            crown_centre = Vec3::new(0.0, 0.8, 0.0);
            for i in 0..6 {
                let a = golden(i) + 0.4;
                let base = Vec3::new(a.cos() * 0.08, -0.03, a.sin() * 0.08);
                let dir = Vec3::new(a.cos() * 0.55, 0.85, a.sin() * 0.55).normalize();
                let len = rng.range(0.9, 1.2);
                let end = base + dir * len;
                let phase = rng.f();
                add(Limb { start: base, end, r0: 0.035, r1: 0.012, phase, trunk: false }, tw, 1, 0.0);
                let mid = base + dir * len * 0.5;
                let sdir = (dir + Vec3::new(-dir.z, 0.0, dir.x) * 0.8).normalize();
                add(Limb { start: mid, end: mid + sdir * 0.5, r0: 0.015, r1: 0.008, phase, trunk: false }, 3, 1, 0.0);
                clusters.push(Cluster { centre: end, attach: mid, phase, radius: 0.45, along: dir });
                clusters.push(Cluster { centre: mid + sdir * 0.5, attach: mid, phase, radius: 0.35, along: sdir });
                clusters.push(Cluster {
                    centre: base + dir * len * 0.35 + Vec3::new(a.cos(), 0.0, a.sin()) * 0.3,
                    attach: base,
                    phase,
                    radius: 0.3,
                    along: dir,
                });
            }
        }
    }
    Skeleton { limbs, clusters, crown_centre }
}

/// The wood of a skeleton as one mesh.
pub fn wood(skel: &Skeleton) -> MeshData {
    let mut mesh = MeshData::default();
    for (limb, sides, rings, droop) in &skel.limbs {
        tube(&mut mesh, limb, *sides, *rings, *droop, 0.8);
    }
    mesh
}

/// Foliage as real leaves around each cluster.
pub fn mesh_foliage(species: Species, skel: &Skeleton) -> MeshData {
    let mut rng = Rng::new(species.seed() ^ 0x1eaf);
    let mut mesh = MeshData::default();
    let (per_cluster, length, width) = match species {
        Species::Broadleaf => (80, 0.26, 0.15),
        Species::Conifer => (9, 0.3, 0.07),
        Species::Birch => (48, 0.17, 0.11),
        Species::Shrub => (30, 0.16, 0.1),
    };
    for c in &skel.clusters {
        for _ in 0..per_cluster {
            let (base, dir) = if species == Species::Conifer {
                // Needle sprays along the branch, pointing outward and forward.
                let s = rng.range(-1.0, 1.0);
                let base = c.centre + c.along * (s * c.radius);
                let dir = (c.along * 0.6 + rng.unit() * 0.8).normalize();
                (base, dir)
            } else {
                let r = c.radius * rng.f().cbrt();
                let base = c.centre + rng.unit() * r;
                let out = (base - c.attach).normalize_or(Vec3::Y);
                let dir = (out * 0.6 + rng.unit() * 0.7 + Vec3::NEG_Y * 0.25).normalize();
                (base, dir)
            };
            // Keep every leaf above the ground (a leaf reaches at most its length below its base).
            let base = Vec3::new(base.x, base.y.max(length * 1.2 + 0.02), base.z);
            let side = rng.unit();
            let outward = (base - skel.crown_centre).normalize_or(Vec3::Y) + Vec3::Y * 0.3;
            let scale = rng.range(0.8, 1.2);
            leaf(&mut mesh, c.attach, base, dir, side, length * scale, width * scale, outward, c.phase);
        }
    }
    mesh
}

/// Foliage as crossed cards: two or three cards per cluster.
pub fn card_foliage(species: Species, skel: &Skeleton) -> MeshData {
    let mut rng = Rng::new(species.seed() ^ 0xca4d);
    let mut mesh = MeshData::default();
    let (cards, size) = match species {
        Species::Broadleaf => (3, 1.9),
        Species::Conifer => (2, 1.5),
        Species::Birch => (2, 1.2),
        Species::Shrub => (2, 0.95),
    };
    for c in &skel.clusters {
        for k in 0..cards {
            let size = size * (c.radius / 0.8).clamp(0.45, 1.2) * rng.range(0.9, 1.1);
            let a = k as f32 * std::f32::consts::PI / cards as f32 + rng.range(0.0, 1.0);
            let (normal, up) = if species == Species::Conifer && c.along.y.abs() < 0.9 {
                // Conifer sprays lie roughly flat along the branch, one tilted each way.
                let side = Vec3::new(-c.along.z, 0.0, c.along.x).normalize();
                let tilt = if k == 0 { 0.35 } else { -0.35 };
                ((Vec3::Y + side * tilt).normalize(), c.along)
            } else {
                (Vec3::new(a.cos(), rng.range(-0.3, 0.3), a.sin()), Vec3::Y + rng.unit().xzy() * 0.2)
            };
            let centre = Vec3::new(c.centre.x, c.centre.y.max(size * 0.75 + 0.02), c.centre.z);
            card(&mut mesh, centre, normal, up, size, skel.crown_centre, c.attach, c.phase);
        }
    }
    mesh
}
