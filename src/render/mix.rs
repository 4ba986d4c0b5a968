//! A 64-bit mix (SplitMix64's finaliser): a well-spread number from a key, for choices that
//! need no RNG state (the leaves' shuffle in `trees/lod.rs`, the blades a lawn's edge keeps in
//! `grass/edges.rs`).

/// Mixes the bits of `z`.
pub(crate) fn mix(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}
