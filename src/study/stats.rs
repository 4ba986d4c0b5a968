//! Paired statistics of two conditions measured on the same participants: the per-participant
//! differences, their mean with a 95 % confidence interval, a paired t-test, a Wilcoxon
//! signed-rank test and Cohen's d for paired samples (d_z).
//!
//! The distributions (Student's t, the standard normal) come from `statrs`; only the rank sums
//! and the exact null distribution of the signed-rank statistic (a count of subsets) are
//! computed here. Every p-value is two-sided.

use serde::Serialize;
use statrs::distribution::{ContinuousCDF, Normal, StudentsT};

/// Above this many non-zero differences (or with tied or zero differences) the Wilcoxon test
/// uses the normal approximation instead of the exact distribution.
pub const WILCOXON_EXACT_MAX: usize = 50;

/// Paired statistics of `differences` (condition B − condition A, one per participant).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PairedStats {
    /// What was subtracted from what, e.g. "manual − ray-casting".
    pub difference: String,
    /// Unit of the differences, e.g. "s".
    pub unit: String,
    /// Number of pairs (participants with both values).
    pub n: usize,
    /// Mean of the differences.
    pub mean_difference: f64,
    /// Sample standard deviation of the differences (n − 1 in the denominator).
    pub sd_difference: f64,
    /// Lower end of the 95 % confidence interval of the mean difference (Student's t).
    pub ci95_low: Option<f64>,
    /// Upper end of the 95 % confidence interval of the mean difference.
    pub ci95_high: Option<f64>,
    /// The paired t statistic, mean / (sd / √n).
    pub t: Option<f64>,
    /// Degrees of freedom of the t-test, n − 1.
    pub df: usize,
    /// Two-sided p-value of the paired t-test.
    pub t_test_p: Option<f64>,
    /// Wilcoxon signed-rank statistic: the sum of the ranks of the positive differences.
    pub wilcoxon_w_plus: f64,
    /// The sum of the ranks of the negative differences.
    pub wilcoxon_w_minus: f64,
    /// Non-zero differences the Wilcoxon test ranked (zero differences are dropped).
    pub wilcoxon_n: usize,
    /// Two-sided p-value of the Wilcoxon signed-rank test.
    pub wilcoxon_p: Option<f64>,
    /// "exact" (the exact null distribution) or "normal" (the normal approximation with
    /// continuity and tie corrections).
    pub wilcoxon_method: String,
    /// Cohen's d for paired samples (d_z): mean difference / sd of the differences.
    pub cohens_dz: Option<f64>,
}

/// Computes the paired statistics, or `None` for fewer than two pairs.
pub fn paired(differences: &[f64], label: &str, unit: &str) -> Option<PairedStats> {
    let n = differences.len();
    if n < 2 || differences.iter().any(|d| !d.is_finite()) {
        return None;
    }
    let mean = differences.iter().sum::<f64>() / n as f64;
    let sd = (differences.iter().map(|d| (d - mean).powi(2)).sum::<f64>() / (n - 1) as f64).sqrt();
    let df = n - 1;
    let se = sd / (n as f64).sqrt();
    let (mut ci_low, mut ci_high, mut t, mut p) = (None, None, None, None);
    if se > 0.0
        && let Ok(dist) = StudentsT::new(0.0, 1.0, df as f64)
    {
        let q = dist.inverse_cdf(0.975);
        ci_low = Some(mean - q * se);
        ci_high = Some(mean + q * se);
        let tv = mean / se;
        t = Some(tv);
        p = Some((2.0 * (1.0 - dist.cdf(tv.abs()))).clamp(0.0, 1.0));
    }
    let w = wilcoxon(differences);
    Some(PairedStats {
        difference: label.to_string(),
        unit: unit.to_string(),
        n,
        mean_difference: mean,
        sd_difference: sd,
        ci95_low: ci_low,
        ci95_high: ci_high,
        t,
        df,
        t_test_p: p,
        wilcoxon_w_plus: w.w_plus,
        wilcoxon_w_minus: w.w_minus,
        wilcoxon_n: w.n,
        wilcoxon_p: w.p,
        wilcoxon_method: w.method.to_string(),
        cohens_dz: (sd > 0.0).then(|| mean / sd),
    })
}

/// The outcome of a Wilcoxon signed-rank test.
#[derive(Clone, Debug, PartialEq)]
pub struct Wilcoxon {
    /// Sum of the ranks of the positive differences.
    pub w_plus: f64,
    /// Sum of the ranks of the negative differences.
    pub w_minus: f64,
    /// Number of non-zero differences.
    pub n: usize,
    /// Two-sided p-value (none without any non-zero difference).
    pub p: Option<f64>,
    /// "exact" or "normal".
    pub method: &'static str,
}

/// The Wilcoxon signed-rank test: zero differences are dropped, tied absolute values get their
/// average rank. The p-value is exact when there are no ties or zeros and at most
/// [`WILCOXON_EXACT_MAX`] differences; otherwise it uses the normal approximation with a
/// continuity correction and the variance corrected for ties.
pub fn wilcoxon(differences: &[f64]) -> Wilcoxon {
    let had_zero = differences.contains(&0.0);
    let mut nz: Vec<f64> = differences.iter().copied().filter(|d| *d != 0.0).collect();
    nz.sort_by(|a, b| a.abs().total_cmp(&b.abs()));
    let n = nz.len();
    // Average ranks over runs of equal absolute values; the tie sizes correct the variance.
    let mut ranks = vec![0.0; n];
    let mut tie_term = 0.0;
    let mut i = 0;
    while i < n {
        let mut j = i;
        while j + 1 < n && nz[j + 1].abs() == nz[i].abs() {
            j += 1;
        }
        let avg = (i + j) as f64 / 2.0 + 1.0;
        ranks[i..=j].iter_mut().for_each(|r| *r = avg);
        let size = (j - i + 1) as f64;
        tie_term += size * size * size - size;
        i = j + 1;
    }
    // Adding 0.0 turns the -0.0 that an empty float sum gives into 0.0.
    let w_plus: f64 = nz.iter().zip(&ranks).filter(|(d, _)| **d > 0.0).map(|(_, r)| r).sum::<f64>() + 0.0;
    let w_minus: f64 = nz.iter().zip(&ranks).filter(|(d, _)| **d < 0.0).map(|(_, r)| r).sum::<f64>() + 0.0;
    if n == 0 {
        return Wilcoxon { w_plus, w_minus, n, p: None, method: "exact" };
    }
    let nf = n as f64;
    if !had_zero && tie_term == 0.0 && n <= WILCOXON_EXACT_MAX {
        // Under the null hypothesis each of the 2^n sign patterns is equally likely; count the
        // patterns whose positive rank sum is at most the smaller observed sum.
        let max = n * (n + 1) / 2;
        let mut counts = vec![0.0f64; max + 1];
        counts[0] = 1.0;
        for r in 1..=n {
            for s in (r..=max).rev() {
                counts[s] += counts[s - r];
            }
        }
        let small = w_plus.min(w_minus).round() as usize;
        let tail: f64 = counts[..=small.min(max)].iter().sum::<f64>() / 2f64.powi(n as i32);
        return Wilcoxon { w_plus, w_minus, n, p: Some((2.0 * tail).min(1.0)), method: "exact" };
    }
    let mu = nf * (nf + 1.0) / 4.0;
    let sigma = (nf * (nf + 1.0) * (2.0 * nf + 1.0) / 24.0 - tie_term / 48.0).sqrt();
    let p = Normal::new(0.0, 1.0).ok().filter(|_| sigma > 0.0).map(|norm| {
        let z = w_plus - mu;
        let z = (z - 0.5 * z.signum()) / sigma;
        (2.0 * norm.cdf(z).min(1.0 - norm.cdf(z))).clamp(0.0, 1.0)
    });
    Wilcoxon { w_plus, w_minus, n, p, method: "normal" }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Student's (1908) sleep data, as in R's `sleep` data set: extra hours of sleep of 10
    /// patients under two drugs. The differences are drug 2 − drug 1.
    const SLEEP_DIFFERENCES: [f64; 10] = [1.2, 2.4, 1.3, 1.3, 0.0, 1.0, 1.8, 0.8, 4.6, 1.4];

    #[test]
    fn the_paired_t_test_matches_the_textbook_sleep_example() {
        let s = paired(&SLEEP_DIFFERENCES, "drug 2 − drug 1", "h").unwrap();
        // R: t.test(extra ~ group, data = sleep, paired = TRUE) prints t = -4.0621, df = 9,
        // p-value = 0.002833, 95 percent CI -2.4598858 -0.7001142, mean difference -1.58
        // (drug 1 − drug 2; here the sign is the other way round).
        assert_eq!(s.n, 10);
        assert_eq!(s.df, 9);
        assert!((s.mean_difference - 1.58).abs() < 1e-12);
        assert!((s.t.unwrap() - 4.0621).abs() < 5e-4, "{:?}", s.t);
        assert!((s.t_test_p.unwrap() - 0.002833).abs() < 5e-6, "{:?}", s.t_test_p);
        assert!((s.ci95_low.unwrap() - 0.7001142).abs() < 1e-6, "{:?}", s.ci95_low);
        assert!((s.ci95_high.unwrap() - 2.4598858).abs() < 1e-6, "{:?}", s.ci95_high);
        // By hand: the squared deviations from 1.58 sum to 13.616, so sd = √(13.616 / 9).
        let sd = (13.616f64 / 9.0).sqrt();
        assert!((s.sd_difference - sd).abs() < 1e-12);
        assert!((s.cohens_dz.unwrap() - 1.58 / sd).abs() < 1e-12);
    }

    #[test]
    fn the_signed_rank_test_matches_the_textbook_sleep_example() {
        // R: wilcox.test(extra ~ group, data = sleep, paired = TRUE) prints V = 0,
        // p-value = 0.009091 (normal approximation: the data have a zero and a tie).
        let w = wilcoxon(&SLEEP_DIFFERENCES);
        assert_eq!(w.n, 9, "the zero difference is dropped");
        assert_eq!(w.w_minus, 0.0);
        assert_eq!(w.w_plus, 45.0, "all nine ranks are positive: 1 + 2 + … + 9");
        assert_eq!(w.method, "normal");
        assert!((w.p.unwrap() - 0.009091).abs() < 5e-6, "{:?}", w.p);
    }

    #[test]
    fn the_exact_signed_rank_distribution_counts_sign_patterns() {
        // Five positive differences: only 1 of the 2^5 sign patterns has W− = 0, so the
        // two-sided p is 2/32 (the smallest p possible with n = 5, a textbook fact).
        let w = wilcoxon(&[0.5, 1.5, 2.5, 3.5, 4.5]);
        assert_eq!((w.w_plus, w.w_minus, w.method), (15.0, 0.0, "exact"));
        assert!((w.p.unwrap() - 2.0 / 32.0).abs() < 1e-15);
        // Differences 1, 2, −3, 4: W− = 3. Patterns with a rank sum ≤ 3 among 16:
        // {}, {1}, {2}, {3}, {1, 2} = 5, so p = 2 · 5/16.
        let w = wilcoxon(&[1.0, 2.0, -3.0, 4.0]);
        assert_eq!((w.w_plus, w.w_minus), (7.0, 3.0));
        assert!((w.p.unwrap() - 10.0 / 16.0).abs() < 1e-15);
    }

    #[test]
    fn too_few_pairs_give_no_statistics() {
        assert!(paired(&[], "b − a", "s").is_none());
        assert!(paired(&[1.0], "b − a", "s").is_none());
        let same = paired(&[2.0, 2.0, 2.0], "b − a", "s").unwrap();
        assert_eq!(same.sd_difference, 0.0);
        assert!(same.t.is_none() && same.cohens_dz.is_none() && same.ci95_low.is_none());
    }
}
