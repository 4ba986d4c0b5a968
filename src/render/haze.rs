//! The aerial perspective's haze by distance, for the CPU ([`haze_share`]) and for the shaders:
//! `lighting.wgsl` imports the piece `haze` ([`SHADER_CONSTANTS`], composed by `shader.rs`),
//! whose `haze_at` mixes the sky's colour over every lit surface with this share. Its constants
//! are `grove_systems::light`'s, which the headset page reads from the snapshot. A leaf of
//! `src/render`: it names no other module. Units: metres.

use std::sync::LazyLock;

pub use grove_systems::light::{HAZE_DEPTH, HAZE_FULL_AT, HAZE_FULL_FROM, HAZE_START};

/// The WGSL piece `haze`: the constants above.
pub static SHADER_CONSTANTS: LazyLock<String> = LazyLock::new(|| {
    [("HAZE_START", HAZE_START), ("HAZE_DEPTH", HAZE_DEPTH), ("HAZE_FULL_FROM", HAZE_FULL_FROM), ("HAZE_FULL_AT", HAZE_FULL_AT)]
        .map(|(name, v)| format!("const {name}: f32 = {v:?};\n"))
        .concat()
});

fn smoothstep(a: f32, b: f32, x: f32) -> f32 {
    let t = ((x - a) / (b - a)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// The share of the haze over a surface `distance` metres from the camera, 0..1: the CPU twin
/// of `haze_at`'s share in `lighting.wgsl`.
pub fn haze_share(distance: f32) -> f32 {
    let exp = 1.0 - (-(distance - HAZE_START).max(0.0) / HAZE_DEPTH).exp();
    exp.max(smoothstep(HAZE_FULL_FROM, HAZE_FULL_AT, distance))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_haze_rises_from_40_m_to_all_of_it_at_590_m() {
        // None within 40 m; 1 - e^-0.4 at 200 m; the larger of 1 - 1/e and the smoothstep at
        // 440 m; all of it from 590 m; never falling.
        assert_eq!(haze_share(10.0), 0.0);
        assert_eq!(haze_share(40.0), 0.0);
        assert!((haze_share(200.0) - (1.0 - (-0.4f32).exp())).abs() < 1e-6);
        let t: f32 = (440.0 - 350.0) / 240.0;
        assert!((haze_share(440.0) - (1.0 - (-1.0f32).exp()).max(t * t * (3.0 - 2.0 * t))).abs() < 1e-6);
        assert_eq!(haze_share(590.0), 1.0);
        let mut last = 0.0;
        for d in (0..700).map(|m| m as f32) {
            let f = haze_share(d);
            assert!((last..=1.0).contains(&f), "{d} m: {f}");
            last = f;
        }
    }

}
