//! Shares of the frame timed in interleaved pairs of frames: one frame without something, one
//! with it, in turn, and the median over the pairs of (with - without) / with. On a shared
//! machine, whose speed drifts while a benchmark runs, two rows timed seconds apart can differ by
//! more than the thing measured (the park's water read anywhere from -25 to +14 % of the frame
//! that way on one build); within a pair the drift moves both frames alike.

/// The share of the frame, per cent, that something adds: `frame(with)` renders and times one
/// frame without it (`false`) or with it (`true`), milliseconds. One frame of each warms up,
/// then `pairs` pairs (at least one), one of each in turn ([`share_of_pairs`]).
pub fn paired_share<E>(pairs: usize, mut frame: impl FnMut(bool) -> Result<f64, E>) -> Result<f64, E> {
    frame(false)?;
    frame(true)?;
    let mut times = Vec::with_capacity(pairs.max(1));
    for _ in 0..pairs.max(1) {
        let without = frame(false)?;
        let with = frame(true)?;
        times.push((without, with));
    }
    Ok(share_of_pairs(&times))
}

/// The median over `(without, with)` frame times of `(with - without) / with`, per cent; 0
/// without pairs. Each pair's frames ran one after the other, so a drift of the machine's speed
/// over the run moves both alike and the median of the pairs' shares stays.
pub fn share_of_pairs(pairs: &[(f64, f64)]) -> f64 {
    let mut shares: Vec<f64> = pairs.iter().filter(|(_, b)| *b > 0.0).map(|(a, b)| (b - a) / b * 100.0).collect();
    if shares.is_empty() {
        return 0.0;
    }
    super::median(&mut shares)
}

#[cfg(test)]
mod tests {
    use super::{paired_share, share_of_pairs};

    #[test]
    fn a_share_is_the_median_of_the_pairs_and_survives_a_drift() {
        // Water adds 10 ms to a 90 ms frame (10 % of 100), while the machine slows down over the
        // run: each pair's frames slow alike, the pairs' shares stay near 10 %.
        let pairs: Vec<(f64, f64)> =
            (0..9).map(|k| (90.0 * (1.0 + 0.1 * k as f64), 100.0 * (1.0 + 0.1 * k as f64))).collect();
        assert!((share_of_pairs(&pairs) - 10.0).abs() < 1e-9);
        // Timing the rows apart, the first half of the run without and the second with, would
        // have given far more: the drift counted as water.
        let apart = (pairs[6].1 - pairs[2].0) / pairs[6].1 * 100.0;
        assert!(apart > 30.0, "{apart}");
        // One pair disturbed by another process does not move the median.
        let mut noisy = pairs.clone();
        noisy[4] = (300.0, 100.0);
        assert!((share_of_pairs(&noisy) - 10.0).abs() < 1e-9);
        // A share is negative where the extra costs nothing and noise falls the other way; no
        // pairs give 0.
        assert!(share_of_pairs(&[(100.0, 95.0)]) < 0.0);
        assert_eq!(share_of_pairs(&[]), 0.0);
    }

    #[test]
    fn frames_are_timed_in_turn_after_one_of_each() {
        // A machine that slows by 5 % a frame; the extra costs 25 % of the frame.
        let mut calls = Vec::new();
        let mut clock = 1.0f64;
        let share = paired_share(4, |with| -> Result<f64, ()> {
            calls.push(with);
            clock *= 1.05;
            Ok(if with { 100.0 } else { 75.0 } * clock)
        })
        .unwrap();
        assert_eq!(calls, [false, true, false, true, false, true, false, true, false, true]);
        // Each pair's second frame is 5 % slower: 1 - 75 / 105 = 28.6 %, whatever the drift so far.
        assert!((share - (1.0 - 75.0 / 105.0) * 100.0).abs() < 1e-9, "{share}");
        assert_eq!(paired_share(3, |_| Err("no device")), Err("no device"));
    }
}
