//! The blades in blocks: the CPU's half of the cull pass.
//!
//! When the patches are uploaded, the blades are put in Morton order of their roots (x, z), so
//! that each run of [`BLOCK_BLADES`] blades, one workgroup of the cull pass, covers a compact
//! piece of lawn, and each block's bounds are kept ([`Block`]). Every frame the CPU sorts the
//! blocks against the view ([`classify`]): a block that no blade of it can be seen from is
//! left out, a block whose every blade is beyond the middle distance goes to a cull pipeline
//! specialised to far blades, and the others to the general one. A software rasteriser such
//! as lavapipe runs every branch of a compute shader for all its invocations, masked, so a far
//! blade in the general pipeline pays for the near and middle blades' code too; in a
//! pipeline without that code it does not. The decisions are conservative: a block is left
//! out, or sent to the far pipeline, only when the cull shader would have dropped, or drawn as
//! far, each of its blades, so the image is the same.
//!
//! Units: metres; +Y up.

use glam::Vec3;

use super::data::{BLADES_PER_INVOCATION, CULL_WORKGROUP, GpuBlade};

/// The blades of a block: one workgroup of the cull pass.
pub const BLOCK_BLADES: u32 = CULL_WORKGROUP * BLADES_PER_INVOCATION;

/// A block's bounds as the cull shader tests its blades: the box of the blades' centres (the
/// root raised by half the blade's length) and the largest blade's length, which is the radius
/// of every blade's test sphere at most.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Block {
    /// The corners of the box of the centres, metres.
    pub min: Vec3,
    /// See `min`.
    pub max: Vec3,
    /// The longest blade, metres.
    pub radius: f32,
}

/// What the cull pass does with a block this frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Class {
    /// No blade of it can be drawn: outside the view or beyond the far distance.
    Hidden,
    /// Every blade of it is at or beyond the middle distance: the far pipeline.
    Far,
    /// Anything else: the general pipeline.
    Mixed,
}

/// Interleaves the bits of two 16-bit numbers (x in the even bits).
fn morton(x: u32, z: u32) -> u32 {
    fn spread(mut v: u32) -> u32 {
        v &= 0xffff;
        v = (v | (v << 8)) & 0x00ff_00ff;
        v = (v | (v << 4)) & 0x0f0f_0f0f;
        v = (v | (v << 2)) & 0x3333_3333;
        v = (v | (v << 1)) & 0x5555_5555;
        v
    }
    spread(x) | (spread(z) << 1)
}

/// Puts `blades` in Morton order of their roots' (x, z) over their bounding square, ties kept
/// in their order; a pure function of the blades.
pub fn spatial_order(blades: &mut Vec<GpuBlade>) {
    let Some(first) = blades.first() else { return };
    let (mut lo, mut hi) = ([first.position[0], first.position[2]], [first.position[0], first.position[2]]);
    for b in blades.iter() {
        for (k, axis) in [0, 2].into_iter().enumerate() {
            lo[k] = lo[k].min(b.position[axis]);
            hi[k] = hi[k].max(b.position[axis]);
        }
    }
    let side = (hi[0] - lo[0]).max(hi[1] - lo[1]).max(1e-6);
    let cell = |v: f32, k: usize| (((v - lo[k]) / side * 65535.0) as u32).min(65535);
    let mut keyed: Vec<(u32, usize)> =
        blades.iter().enumerate().map(|(i, b)| (morton(cell(b.position[0], 0), cell(b.position[2], 1)), i)).collect();
    keyed.sort_unstable();
    *blades = keyed.into_iter().map(|(_, i)| blades[i]).collect();
}

/// The bounds of each run of [`BLOCK_BLADES`] blades (the last may be shorter).
pub fn block_bounds(blades: &[GpuBlade]) -> Vec<Block> {
    blades
        .chunks(BLOCK_BLADES as usize)
        .map(|run| {
            let centre = |b: &GpuBlade| Vec3::new(b.position[0], b.position[1] + 0.5 * b.height, b.position[2]);
            let mut block = Block { min: Vec3::splat(f32::MAX), max: Vec3::splat(f32::MIN), radius: 0.0 };
            for b in run {
                block.min = block.min.min(centre(b));
                block.max = block.max.max(centre(b));
                block.radius = block.radius.max(b.height);
            }
            block
        })
        .collect()
}

/// The class of `block` for a camera at `camera` with the inward frustum `planes`
/// (`data::frustum_planes`), no blade drawn beyond `far_distance` and far blades from
/// `lod_mid` on (metres). The cull shader draws a blade whose centre is at distance d when
/// d ≤ `far_distance` and its sphere (radius: its length) is inside every plane, and draws
/// it as far when d ≥ `lod_mid`; the margins keep a block whose nearest point is within
/// rounding of a limit in the general pipeline.
pub fn classify(block: &Block, planes: &[[f32; 4]; 6], camera: Vec3, far_distance: f32, lod_mid: f32) -> Class {
    let nearest = camera.clamp(block.min, block.max).distance(camera);
    if nearest > far_distance * (1.0 + 1e-5) + 1e-4 {
        return Class::Hidden;
    }
    for p in planes {
        let n = Vec3::new(p[0], p[1], p[2]);
        // The corner of the box furthest along the plane's inward normal.
        let corner = Vec3::select(n.cmpge(Vec3::ZERO), block.max, block.min);
        if n.dot(corner) + p[3] < -block.radius - 1e-4 {
            return Class::Hidden;
        }
    }
    if nearest >= lod_mid * (1.0 + 1e-5) + 1e-4 { Class::Far } else { Class::Mixed }
}

/// The blocks the general pipeline culls this frame, then those the far pipeline culls, as
/// one list of block indices, with the length of the first part.
pub fn block_lists(
    blocks: &[Block],
    planes: &[[f32; 4]; 6],
    camera: Vec3,
    far_distance: f32,
    lod_mid: f32,
) -> (Vec<u32>, u32) {
    let mut mixed = Vec::new();
    let mut far = Vec::new();
    for (i, b) in blocks.iter().enumerate() {
        match classify(b, planes, camera, far_distance, lod_mid) {
            Class::Hidden => {}
            Class::Far => far.push(i as u32),
            Class::Mixed => mixed.push(i as u32),
        }
    }
    let split = mixed.len() as u32;
    mixed.extend(far);
    (mixed, split)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn blade(x: f32, z: f32, height: f32) -> GpuBlade {
        GpuBlade { position: [x, 0.0, z], height, yaw: 0.0, bend: 0.0, width: 0.01, packed: 0 }
    }

    /// Planes that keep everything: normal +Y, far below.
    fn open() -> [[f32; 4]; 6] {
        [[0.0, 1.0, 0.0, 1e6]; 6]
    }

    #[test]
    fn morton_interleaves_bits() {
        // x = 0b11 → bits 0 and 2; z = 0b01 → bit 1.
        assert_eq!(morton(0b11, 0b01), 0b111);
        assert_eq!(morton(0, 1), 2);
        assert_eq!(morton(1, 0), 1);
        assert_eq!(morton(0xffff, 0), 0x5555_5555);
    }

    #[test]
    fn spatial_order_is_a_permutation_into_compact_blocks() {
        // A 128 × 64 grid of blades, 10 cm apart, in row order: a run of 1024 is 8 rows of
        // 12.8 m; in Morton order it should be a 3.2 × 3.2 m square (32 × 32 blades).
        let mut blades: Vec<GpuBlade> =
            (0..64).flat_map(|r| (0..128).map(move |c| blade(c as f32 * 0.1, r as f32 * 0.1, 0.3))).collect();
        let before: Vec<[u32; 2]> = blades.iter().map(|b| [b.position[0].to_bits(), b.position[2].to_bits()]).collect();
        spatial_order(&mut blades);
        let mut a = before.clone();
        let mut b: Vec<[u32; 2]> = blades.iter().map(|b| [b.position[0].to_bits(), b.position[2].to_bits()]).collect();
        a.sort_unstable();
        b.sort_unstable();
        assert_eq!(a, b, "the same blades");
        for block in block_bounds(&blades) {
            let size = block.max - block.min;
            assert!(size.x < 3.2 && size.z < 3.2, "a block spans {size}");
        }
    }

    #[test]
    fn bounds_hold_the_centres_and_the_longest_blade() {
        let blades = [blade(1.0, 2.0, 0.2), blade(-1.0, 5.0, 0.6)];
        let b = block_bounds(&blades);
        assert_eq!(b.len(), 1);
        assert_eq!(b[0].min, Vec3::new(-1.0, 0.1, 2.0));
        assert_eq!(b[0].max, Vec3::new(1.0, 0.3, 5.0));
        assert_eq!(b[0].radius, 0.6);
        assert_eq!(block_bounds(&vec![blade(0.0, 0.0, 0.3); 2 * BLOCK_BLADES as usize + 1]).len(), 3);
    }

    #[test]
    fn classes_by_distance() {
        // A 1 m box of centres from x = 10 to 11; the camera at the origin.
        let block = Block { min: Vec3::new(10.0, 0.0, 0.0), max: Vec3::new(11.0, 0.5, 1.0), radius: 0.5 };
        let camera = Vec3::ZERO;
        // Nearest point 10 m away.
        assert_eq!(classify(&block, &open(), camera, 60.0, 9.0), Class::Far);
        assert_eq!(classify(&block, &open(), camera, 60.0, 10.5), Class::Mixed);
        assert_eq!(classify(&block, &open(), camera, 9.9, 5.0), Class::Hidden);
        // Exactly at the middle distance: kept general (the margin).
        assert_eq!(classify(&block, &open(), camera, 60.0, 10.0), Class::Mixed);
        // Exactly at the far distance: drawn.
        assert_ne!(classify(&block, &open(), camera, 10.0, 5.0), Class::Hidden);
    }

    #[test]
    fn classes_by_plane() {
        let block = Block { min: Vec3::new(10.0, 0.0, 0.0), max: Vec3::new(11.0, 0.5, 1.0), radius: 0.5 };
        let mut planes = open();
        // Keep x ≤ 9: the box's furthest corner along -x is x = 10, 1 m out, beyond the radius.
        planes[0] = [-1.0, 0.0, 0.0, 9.0];
        assert_eq!(classify(&block, &planes, Vec3::ZERO, 60.0, 1.0), Class::Hidden);
        // Keep x ≤ 9.6: 0.4 m out, within the longest blade's sphere.
        planes[0] = [-1.0, 0.0, 0.0, 9.6];
        assert_eq!(classify(&block, &planes, Vec3::ZERO, 60.0, 1.0), Class::Far);
        // Keep x ≥ 10.5: half the box is in.
        planes[0] = [1.0, 0.0, 0.0, -10.5];
        assert_eq!(classify(&block, &planes, Vec3::ZERO, 60.0, 1.0), Class::Far);
    }

    /// The cull shader's own test of a blade (cull.wgsl `cull_blade`), in the same f32 steps:
    /// drawn, and its distance.
    fn shader_test(b: &GpuBlade, planes: &[[f32; 4]; 6], camera: Vec3, far_distance: f32) -> (bool, f32) {
        let centre = Vec3::new(b.position[0], b.position[1] + 0.5 * b.height, b.position[2]);
        let d = centre.distance(camera);
        let inside =
            d <= far_distance && planes.iter().all(|p| Vec3::new(p[0], p[1], p[2]).dot(centre) + p[3] >= -b.height);
        (inside, d)
    }

    #[test]
    fn classes_are_conservative_against_the_shaders_test() {
        use rand::{RngExt, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(18);
        let (far_distance, lod_mid) = (60.0, 10.5);
        let mut seen = [0usize; 3];
        for _ in 0..400 {
            // A camera somewhere above a 160 m square, looking somewhere down the slope.
            let mut r = |lo: f32, hi: f32| lo + (hi - lo) * rng.random::<f32>();
            let eye = Vec3::new(r(-80.0, 80.0), r(0.5, 30.0), r(-80.0, 80.0));
            let target = Vec3::new(r(-80.0, 80.0), 0.0, r(-80.0, 80.0));
            let view_proj = glam::camera::rh::proj::directx::perspective(r(0.5, 1.5), r(1.0, 2.0), 0.05, 600.0)
                * glam::camera::rh::view::look_at_mat4(eye, target, Vec3::Y);
            let planes = super::super::data::frustum_planes(view_proj);
            // A block of 200 blades in a random square of up to 4 m, up to 40 m ahead of the eye.
            let ahead = (target - eye).with_y(0.0).normalize_or(Vec3::X);
            let c = eye + ahead * r(0.0, 40.0) + ahead.cross(Vec3::Y) * r(-8.0, 8.0);
            let (cx, cz, side) = (c.x, c.z, r(0.2, 4.0));
            let blades: Vec<GpuBlade> = (0..200)
                .map(|_| GpuBlade {
                    position: [cx + r(0.0, side), r(-0.2, 0.2), cz + r(0.0, side)],
                    height: r(0.05, 0.6),
                    yaw: 0.0,
                    bend: 0.0,
                    width: 0.01,
                    packed: 0,
                })
                .collect();
            let block = block_bounds(&blades)[0];
            let class = classify(&block, &planes, eye, far_distance, lod_mid);
            for b in &blades {
                let (drawn, d) = shader_test(b, &planes, eye, far_distance);
                match class {
                    Class::Hidden => assert!(!drawn, "a hidden block holds a drawn blade at {:?}", b.position),
                    Class::Far => assert!(!drawn || d >= lod_mid, "a far block holds a blade {d} m away"),
                    Class::Mixed => {}
                }
            }
            seen[class as usize] += 1;
        }
        // Each class came up, so the checks above were exercised.
        assert!(seen.iter().all(|&n| n > 10), "classes seen: {seen:?}");
    }

    #[test]
    fn lists_put_mixed_blocks_first() {
        let at = |x: f32| Block { min: Vec3::new(x, 0.0, 0.0), max: Vec3::new(x + 1.0, 0.5, 1.0), radius: 0.5 };
        // Blocks at 20 m (far), 2 m (mixed), 100 m (hidden), 3 m (mixed), 30 m (far).
        let blocks = [at(20.0), at(2.0), at(100.0), at(3.0), at(30.0)];
        let (list, split) = block_lists(&blocks, &open(), Vec3::ZERO, 60.0, 10.0);
        assert_eq!(list, vec![1, 3, 0, 4]);
        assert_eq!(split, 2);
    }
}
