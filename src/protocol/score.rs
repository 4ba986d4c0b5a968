//! The published scoring of the shipped instruments: the System Usability Scale (Brooke 1996:
//! odd items score − 1, even items 5 − score, the sum × 2.5, 0–100) and raw NASA-TLX (the mean of
//! the six subscales, 0–100, without the pairwise weights).

use super::format::{Instrument, Scoring};

/// The score of one participant's answers to `ins` (in item order, `None` where unanswered), or
/// `None` when the instrument has no scoring or an item it needs is unanswered.
pub fn score(ins: &Instrument, answers: &[Option<i64>]) -> Option<f64> {
    if answers.len() != ins.items.len() || answers.iter().any(|a| a.is_none()) {
        return None;
    }
    let v: Vec<i64> = answers.iter().flatten().copied().collect();
    match ins.scoring {
        Scoring::None => None,
        Scoring::Sus => Some(sus(&v)),
        Scoring::RawTlx => Some(raw_tlx(&v)),
    }
}

/// SUS from ten answers 1–5 in item order.
pub fn sus(answers: &[i64]) -> f64 {
    let sum: i64 = answers.iter().enumerate().map(|(i, s)| if i % 2 == 0 { s - 1 } else { 5 - s }).sum();
    sum as f64 * 2.5
}

/// Raw TLX: the mean of the subscales.
pub fn raw_tlx(answers: &[i64]) -> f64 {
    answers.iter().sum::<i64>() as f64 / answers.len().max(1) as f64
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sus_spans_0_to_100_and_matches_a_worked_example() {
        assert_eq!(sus(&[5, 1, 5, 1, 5, 1, 5, 1, 5, 1]), 100.0);
        assert_eq!(sus(&[1, 5, 1, 5, 1, 5, 1, 5, 1, 5]), 0.0);
        assert_eq!(sus(&[3; 10]), 50.0);
        // 4,2,4,2,3,3,4,1,4,2 → (3+3+3+3+2+2+3+4+3+3) = 29 → 72.5
        assert_eq!(sus(&[4, 2, 4, 2, 3, 3, 4, 1, 4, 2]), 72.5);
    }

    #[test]
    fn raw_tlx_is_the_mean_and_needs_every_subscale() {
        assert_eq!(raw_tlx(&[10, 20, 30, 40, 50, 60]), 35.0);
        let tlx = crate::protocol::shipped::get("nasa-tlx").expect("shipped");
        assert_eq!(score(&tlx, &[Some(10), Some(20), Some(30), Some(40), Some(50), None]), None);
        assert_eq!(score(&tlx, &[Some(0), Some(0), Some(0), Some(0), Some(0), Some(30)]), Some(5.0));
    }
}
