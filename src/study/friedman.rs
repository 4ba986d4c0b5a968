//! Statistics of k ≥ 3 conditions measured on the same participants: the Friedman test with
//! Kendall's W as its effect size, then post-hoc pairwise comparisons (the paired statistics of
//! [`super::stats`]: Wilcoxon signed-rank test, mean difference with its 95 % confidence
//! interval, Cohen's d_z) with Holm's correction of the Wilcoxon p-values. For k = 2 the report
//! keeps its paired analysis unchanged.
//!
//! The chi-squared distribution comes from `statrs`; only the within-participant ranks are
//! computed here.

use serde::Serialize;
use statrs::distribution::{ChiSquared, ContinuousCDF};

use super::stats::{PairedStats, paired};

/// The Friedman rank test of k conditions over n participants (blocks).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Friedman {
    /// Participants with a value in every condition.
    pub n: usize,
    /// Conditions.
    pub k: usize,
    /// Each condition's mean rank within participants (1 = fastest).
    pub mean_ranks: Vec<f64>,
    /// The Friedman chi-squared statistic, corrected for ties within participants.
    pub chi_squared: f64,
    /// Degrees of freedom, k − 1.
    pub df: usize,
    /// Its p-value from the chi-squared distribution.
    pub p: f64,
    /// Kendall's coefficient of concordance W = chi² / (n (k − 1)), from 0 (no agreement) to 1.
    pub kendall_w: f64,
}

/// Average ranks (1-based) of the values of one row; ties get the mean of their ranks. Also
/// returns the sum of t³ − t over the row's groups of ties.
fn row_ranks(row: &[f64]) -> (Vec<f64>, f64) {
    let mut order: Vec<usize> = (0..row.len()).collect();
    order.sort_by(|&a, &b| row[a].total_cmp(&row[b]));
    let mut ranks = vec![0.0; row.len()];
    let mut ties = 0.0;
    let mut i = 0;
    while i < order.len() {
        let mut j = i;
        while j + 1 < order.len() && row[order[j + 1]] == row[order[i]] {
            j += 1;
        }
        let avg = (i + j) as f64 / 2.0 + 1.0;
        for &o in &order[i..=j] {
            ranks[o] = avg;
        }
        let t = (j - i + 1) as f64;
        ties += t * t * t - t;
        i = j + 1;
    }
    (ranks, ties)
}

/// The Friedman test over `rows` (one per participant, one value per condition). `None` for
/// fewer than two participants or conditions, rows of different lengths, a value that is not
/// finite, or rows that are all ties.
pub fn friedman(rows: &[Vec<f64>]) -> Option<Friedman> {
    let n = rows.len();
    let k = rows.first()?.len();
    if n < 2 || k < 2 || rows.iter().any(|r| r.len() != k || r.iter().any(|v| !v.is_finite())) {
        return None;
    }
    let mut sums = vec![0.0; k];
    let mut ties = 0.0;
    for row in rows {
        let (ranks, t) = row_ranks(row);
        sums.iter_mut().zip(&ranks).for_each(|(s, r)| *s += r);
        ties += t;
    }
    let (nf, kf) = (n as f64, k as f64);
    let expected = nf * (kf + 1.0) / 2.0;
    let spread: f64 = sums.iter().map(|s| (s - expected).powi(2)).sum();
    let denominator = nf * kf * (kf + 1.0) - ties / (kf - 1.0);
    if denominator <= 0.0 {
        return None;
    }
    let chi_squared = 12.0 * spread / denominator;
    let p = ChiSquared::new(kf - 1.0).ok()?.sf(chi_squared);
    Some(Friedman {
        n,
        k,
        mean_ranks: sums.iter().map(|s| s / nf).collect(),
        chi_squared,
        df: k - 1,
        p,
        kendall_w: chi_squared / (nf * (kf - 1.0)),
    })
}

/// Holm's step-down adjustment of p-values (Holm 1979), in the input order: the i-th smallest
/// of m p-values is multiplied by m − i + 1, and the adjusted values are made monotone and
/// capped at 1.
pub fn holm(p: &[f64]) -> Vec<f64> {
    let m = p.len();
    let mut order: Vec<usize> = (0..m).collect();
    order.sort_by(|&a, &b| p[a].total_cmp(&p[b]));
    let mut out = vec![0.0; m];
    let mut running: f64 = 0.0;
    for (i, &o) in order.iter().enumerate() {
        running = running.max(((m - i) as f64 * p[o]).min(1.0));
        out[o] = running;
    }
    out
}

/// One post-hoc comparison of two conditions.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PostHoc {
    /// The first condition.
    pub a: String,
    /// The second condition; the differences are b − a.
    pub b: String,
    /// The paired statistics of b − a (Wilcoxon, mean difference and its CI, d_z).
    pub stats: PairedStats,
    /// The Wilcoxon p-value after Holm's correction over all pairs.
    pub p_holm: Option<f64>,
}

/// The analysis of k conditions: Friedman, then every pair.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Conditions {
    /// The conditions, in column order.
    pub names: Vec<String>,
    /// The omnibus test.
    pub friedman: Friedman,
    /// Every pair (i < j), in order.
    pub pairs: Vec<PostHoc>,
}

/// Analyses `rows` (one per participant, a value per condition in `names` order) in `unit`.
pub fn analyse(names: &[String], rows: &[Vec<f64>], unit: &str) -> Option<Conditions> {
    let friedman = friedman(rows)?;
    if names.len() != friedman.k {
        return None;
    }
    let mut pairs = Vec::new();
    for i in 0..names.len() {
        for j in i + 1..names.len() {
            let d: Vec<f64> = rows.iter().map(|r| r[j] - r[i]).collect();
            let stats = paired(&d, &format!("{} − {}", names[j], names[i]), unit)?;
            pairs.push(PostHoc { a: names[i].clone(), b: names[j].clone(), stats, p_holm: None });
        }
    }
    let ps: Vec<f64> = pairs.iter().map(|p| p.stats.wilcoxon_p.unwrap_or(1.0)).collect();
    for (pair, adj) in pairs.iter_mut().zip(holm(&ps)) {
        pair.p_holm = pair.stats.wilcoxon_p.map(|_| adj);
    }
    Some(Conditions { names: names.to_vec(), friedman, pairs })
}

fn num(x: Option<f64>, digits: usize) -> String {
    x.map_or_else(|| "–".to_string(), |v| format!("{v:.digits$}"))
}

/// A p-value: four decimals, or three significant digits below 0.001.
fn pval(p: Option<f64>) -> String {
    match p {
        Some(v) if v < 1e-3 => format!("{v:.3e}"),
        other => num(other, 4),
    }
}

/// The analysis as a Markdown section.
pub fn markdown(c: &Conditions, what: &str) -> String {
    let f = &c.friedman;
    let mut s = format!(
        "### {what}: {} conditions\n\nFriedman test over {} participants: χ²({}) = {:.3}, p = {}; Kendall's W = {:.3}.\n\n| condition | mean rank |\n|---|---|\n",
        f.k,
        f.n,
        f.df,
        f.chi_squared,
        pval(Some(f.p)),
        f.kendall_w
    );
    for (name, r) in c.names.iter().zip(&f.mean_ranks) {
        s += &format!("| {name} | {r:.2} |\n");
    }
    s += "\nPost-hoc Wilcoxon signed-rank tests, Holm-corrected:\n\n| difference | mean | 95 % CI | d_z | W+ | p | p (Holm) |\n|---|---|---|---|---|---|---|\n";
    for p in &c.pairs {
        let st = &p.stats;
        s += &format!(
            "| {} | {:.2} {} | [{}, {}] | {} | {} | {} | {} |\n",
            st.difference,
            st.mean_difference,
            st.unit,
            num(st.ci95_low, 2),
            num(st.ci95_high, 2),
            num(st.cohens_dz, 2),
            st.wilcoxon_w_plus,
            pval(st.wilcoxon_p),
            pval(p.p_holm)
        );
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Hollander & Wolfe, *Nonparametric Statistical Methods* (1st ed., Wiley 1973), p. 140ff:
    /// times (s) of 22 baseball players rounding first base by three methods (round out, narrow
    /// angle, wide angle). The example of R's `friedman.test` documentation prints for it
    /// "Friedman chi-squared = 11.143, df = 2, p-value = 0.003805".
    const ROUNDING: [[f64; 3]; 22] = [
        [5.40, 5.50, 5.55],
        [5.85, 5.70, 5.75],
        [5.20, 5.60, 5.50],
        [5.55, 5.50, 5.40],
        [5.90, 5.85, 5.70],
        [5.45, 5.55, 5.60],
        [5.40, 5.40, 5.35],
        [5.45, 5.50, 5.35],
        [5.25, 5.15, 5.00],
        [5.85, 5.80, 5.70],
        [5.25, 5.20, 5.10],
        [5.65, 5.55, 5.45],
        [5.60, 5.35, 5.45],
        [5.05, 5.00, 4.95],
        [5.50, 5.50, 5.40],
        [5.45, 5.55, 5.50],
        [5.55, 5.55, 5.35],
        [5.45, 5.50, 5.55],
        [5.50, 5.45, 5.25],
        [5.65, 5.60, 5.40],
        [5.70, 5.65, 5.55],
        [6.30, 6.30, 6.25],
    ];

    #[test]
    fn friedman_matches_the_published_first_base_example() {
        let rows: Vec<Vec<f64>> = ROUNDING.iter().map(|r| r.to_vec()).collect();
        let f = friedman(&rows).unwrap();
        assert_eq!((f.n, f.k, f.df), (22, 3, 2));
        assert!((f.chi_squared - 11.143).abs() < 5e-4, "{}", f.chi_squared);
        assert!((f.p - 0.003805).abs() < 5e-7, "{}", f.p);
        // The wide angle is fastest: the lowest mean rank.
        assert!(f.mean_ranks[2] < f.mean_ranks[1] && f.mean_ranks[2] < f.mean_ranks[0]);
    }

    /// Hollander & Wolfe (1973), p. 29f, as in the example of R's `wilcox.test`: Hamilton
    /// depression scale factor IV before (x) and after (y) a tranquilizer, nine patients.
    /// `wilcox.test(x, y, paired = TRUE, alternative = "greater")` prints "V = 40, p-value =
    /// 0.01953"; the two-sided p of the symmetric exact distribution is twice that.
    #[test]
    fn the_post_hoc_wilcoxon_matches_the_published_depression_example() {
        let x = [1.83, 0.50, 1.62, 2.48, 1.68, 1.88, 1.55, 3.06, 1.30];
        let y = [0.878, 0.647, 0.598, 2.05, 1.06, 1.29, 1.06, 3.14, 1.29];
        // Condition a = y, b = x: the differences b − a are x − y, whose W+ is R's V.
        let rows: Vec<Vec<f64>> = x.iter().zip(&y).map(|(x, y)| vec![*y, *x, x + y]).collect();
        let c = analyse(&["after".into(), "before".into(), "sum".into()], &rows, "").unwrap();
        let pair = &c.pairs[0];
        assert_eq!(pair.stats.wilcoxon_w_plus, 40.0);
        assert!((pair.stats.wilcoxon_p.unwrap() - 2.0 * 0.01953).abs() < 1e-4, "{:?}", pair.stats.wilcoxon_p);
        // Holm over three pairs never lowers a p-value.
        assert!(c.pairs.iter().all(|p| p.p_holm.unwrap() >= p.stats.wilcoxon_p.unwrap()));
    }

    #[test]
    fn holm_follows_its_definition() {
        // Sorted: 0.005·4 = 0.02, 0.01·3 = 0.03, 0.03·2 = 0.06, 0.04·1 = 0.04 → kept at 0.06.
        let adj = holm(&[0.01, 0.04, 0.03, 0.005]);
        let want = [0.03, 0.06, 0.06, 0.02];
        assert!(adj.iter().zip(want).all(|(a, w)| (a - w).abs() < 1e-12), "{adj:?}");
        assert_eq!(holm(&[0.6, 0.7]), vec![1.0, 1.0]);
    }

    #[test]
    fn ties_within_a_row_share_their_rank_and_bad_input_gives_none() {
        let (r, t) = row_ranks(&[2.0, 1.0, 2.0]);
        assert_eq!(r, vec![2.5, 1.0, 2.5]);
        assert_eq!(t, 6.0);
        assert!(friedman(&[vec![1.0, 2.0, 3.0]]).is_none());
        assert!(friedman(&[vec![1.0, 2.0], vec![1.0]]).is_none());
        assert!(friedman(&[vec![1.0, f64::NAN], vec![1.0, 2.0]]).is_none());
        assert!(friedman(&[vec![1.0, 1.0], vec![2.0, 2.0]]).is_none());
    }
}
