//! Counterbalanced condition orders: a balanced Latin square (Williams 1949). Every condition
//! appears once in every position, and for an even k every condition follows every other
//! exactly once; for an odd k the square is paired with its mirror image (2k rows), which
//! balances first-order carry-over as well.

/// The rows of the balanced Latin square of `k` conditions (0-based): k rows for an even k,
/// 2k for an odd one. Participant p takes row `p % rows.len()`.
pub fn williams(k: usize) -> Vec<Vec<usize>> {
    if k == 0 {
        return Vec::new();
    }
    // The first row: 0, k−1, 1, k−2, 2, … (successive differences all distinct mod k); row r
    // adds r to every entry (mod k).
    let mut first = Vec::with_capacity(k);
    let (mut low, mut high) = (0usize, k);
    for i in 0..k {
        if i % 2 == 0 {
            first.push(low);
            low += 1;
        } else {
            high -= 1;
            first.push(high);
        }
    }
    let mut rows: Vec<Vec<usize>> = (0..k).map(|r| first.iter().map(|c| (c + r) % k).collect()).collect();
    if k % 2 == 1 {
        let mirrored: Vec<Vec<usize>> = rows.iter().map(|r| r.iter().rev().copied().collect()).collect();
        rows.extend(mirrored);
    }
    rows
}

/// The order in which participant `p` (0-based) does `k` conditions.
pub fn order(p: usize, k: usize) -> Vec<usize> {
    let rows = williams(k);
    if rows.is_empty() {
        return Vec::new();
    }
    rows[p % rows.len()].clone()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn balanced(rows: &[Vec<usize>], k: usize) {
        // Every condition once per row, and equally often in every position.
        for r in rows {
            let mut s = r.clone();
            s.sort_unstable();
            assert_eq!(s, (0..k).collect::<Vec<_>>());
        }
        for pos in 0..k {
            for c in 0..k {
                assert_eq!(
                    rows.iter().filter(|r| r[pos] == c).count(),
                    rows.len() / k,
                    "position {pos}, condition {c}"
                );
            }
        }
        // Every ordered pair (a then b at once) equally often.
        let per = rows.len() * (k - 1) / (k * (k - 1));
        for a in 0..k {
            for b in (0..k).filter(|b| *b != a) {
                let n = rows.iter().map(|r| r.windows(2).filter(|w| w[0] == a && w[1] == b).count()).sum::<usize>();
                assert_eq!(n, per, "{a} then {b}");
            }
        }
    }

    #[test]
    fn two_conditions_alternate_as_the_two_task_study_did() {
        assert_eq!(williams(2), vec![vec![0, 1], vec![1, 0]]);
        assert_eq!(order(0, 2), vec![0, 1]);
        assert_eq!(order(3, 2), vec![1, 0]);
    }

    #[test]
    fn squares_are_balanced_for_position_and_carry_over() {
        for k in 2..=6 {
            let rows = williams(k);
            assert_eq!(rows.len(), if k % 2 == 0 { k } else { 2 * k });
            balanced(&rows, k);
        }
        assert_eq!(williams(3)[0], vec![0, 2, 1]);
    }
}
