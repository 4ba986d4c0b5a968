//! Rounding done with plain arithmetic and integer conversions, with the very results of
//! `f32::floor`, `f64::fract` and `f64 % 2.0`: the target's baseline instruction set (x86-64
//! with SSE2) has no rounding instruction, so those are calls into the maths library, and the
//! wind system makes several per tree per tick.

/// `x.floor()`, the same value for every `x` (zeros, infinities and NaN included).
#[inline]
pub fn floor(x: f32) -> f32 {
    // From 2^23 on every f32 is an integer; NaN, the infinities and both zeros are their own
    // floor too.
    if !(x.abs() < 8_388_608.0) || x == 0.0 {
        return x;
    }
    // Truncation toward zero, exact below 2^23; one less for a negative non-integer.
    let t = x as i32 as f32;
    if t > x { t - 1.0 } else { t }
}

/// `x.fract()` (`x − x.trunc()`), the same value for every `x`.
#[inline]
pub fn fract(x: f64) -> f64 {
    // From 2^52 on every f64 is an integer; zeros, infinities and NaN go to the library.
    if !(x.abs() < 4_503_599_627_370_496.0) || x == 0.0 {
        return x.fract();
    }
    // The truncation, exact below 2^52 (a zero of either sign subtracts the same from a
    // non-zero `x`).
    x - x as i64 as f64
}

/// `t % 2.0`, the same value for every `t`.
#[inline]
pub fn rem_2(t: f64) -> f64 {
    if !(t > 0.0 && t < 4_503_599_627_370_496.0) {
        return t % 2.0;
    }
    // t − 2·trunc(t / 2): the halving, the truncation and the doubling are exact, and the
    // difference, the remainder itself, is representable, so the subtraction is exact too.
    t - 2.0 * ((t * 0.5) as i64 as f64)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Edge values and a sweep of bit patterns across every exponent.
    fn f32s() -> impl Iterator<Item = f32> {
        let edges = [
            0.0,
            -0.0,
            0.5,
            -0.5,
            1.0,
            -1.0,
            1.5,
            -1.5,
            8_388_607.5,
            -8_388_607.5,
            8_388_608.0,
            -8_388_609.0,
            f32::MIN_POSITIVE,
            -f32::MIN_POSITIVE,
            1e-45,
            -1e-45,
            f32::MAX,
            f32::MIN,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::NAN,
        ];
        edges
            .into_iter()
            .chain((0..400_000u32).map(|i| f32::from_bits(i.wrapping_mul(2_654_435_761).rotate_left(7) ^ i)))
    }

    fn f64s() -> impl Iterator<Item = f64> {
        let edges = [
            0.0,
            -0.0,
            0.5,
            -0.5,
            1.0,
            -1.0,
            2.0,
            -2.0,
            3.0,
            1.999_999_999,
            4_503_599_627_370_495.5,
            4_503_599_627_370_496.0,
            -4_503_599_627_370_495.5,
            f64::MIN_POSITIVE,
            5e-324,
            -5e-324,
            f64::MAX,
            f64::MIN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
        ];
        let ticks = (0..200_000u64).map(|k| k as f64 * (1.0f32 / 60.0) as f64);
        edges
            .into_iter()
            .chain(ticks)
            .chain((0..400_000u64).map(|i| f64::from_bits(i.wrapping_mul(0x9E37_79B9_7F4A_7C15).rotate_left(11) ^ i)))
    }

    #[test]
    fn the_values_are_the_libraries_bit_for_bit() {
        for x in f32s() {
            assert_eq!(floor(x).to_bits(), x.floor().to_bits(), "floor({x:e})");
        }
        for x in f64s() {
            assert_eq!(fract(x).to_bits(), x.fract().to_bits(), "fract({x:e})");
            assert_eq!(rem_2(x).to_bits(), (x % 2.0).to_bits(), "rem_2({x:e})");
        }
    }
}
