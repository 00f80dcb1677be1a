//! Significance: one-sided paired tests on per-run differences (the sign-flip randomization
//! test the diagnosis uses, and the Wilcoxon signed-rank test), and Holm's correction for
//! testing several candidates and channels at once.

/// Exact null distribution up to this many non-zero differences (without ties).
const EXACT_MAX_N: usize = 40;

/// One-sided p-value of the Wilcoxon signed-rank test for H1: the differences tend to be > 0.
/// Zero differences are dropped; ties share average ranks (then the normal approximation
/// with tie and continuity correction is used, as it is for n > 40). Returns 1 for no data.
pub fn wilcoxon_greater(differences: &[f64]) -> f64 {
    let mut d: Vec<f64> = differences
        .iter()
        .copied()
        .filter(|x| *x != 0.0 && x.is_finite())
        .collect();
    let n = d.len();
    if n == 0 {
        return 1.0;
    }
    d.sort_by(|a, b| a.abs().total_cmp(&b.abs()));
    // Average ranks over ties of |d|.
    let mut ranks = vec![0.0; n];
    let mut tie_term = 0.0;
    let mut i = 0;
    while i < n {
        let mut j = i;
        while j + 1 < n && d[j + 1].abs() == d[i].abs() {
            j += 1;
        }
        let rank = (i + j) as f64 / 2.0 + 1.0;
        ranks[i..=j].iter_mut().for_each(|r| *r = rank);
        let t = (j - i + 1) as f64;
        tie_term += t * t * t - t;
        i = j + 1;
    }
    let w_plus: f64 = d
        .iter()
        .zip(&ranks)
        .filter(|(x, _)| **x > 0.0)
        .map(|(_, r)| r)
        .sum();
    if tie_term == 0.0 && n <= EXACT_MAX_N {
        return exact_upper_tail(n, w_plus.round() as usize);
    }
    let nf = n as f64;
    let mean = nf * (nf + 1.0) / 4.0;
    let var = nf * (nf + 1.0) * (2.0 * nf + 1.0) / 24.0 - tie_term / 48.0;
    if var <= 0.0 {
        return 1.0;
    }
    let z = (w_plus - mean - 0.5) / var.sqrt();
    normal_upper_tail(z)
}

/// P(W+ >= w) under the null for n untied ranks 1..n (each sign equally likely).
fn exact_upper_tail(n: usize, w: usize) -> f64 {
    let max = n * (n + 1) / 2;
    // counts[s]: number of sign patterns with rank sum s.
    let mut counts = vec![0f64; max + 1];
    counts[0] = 1.0;
    for r in 1..=n {
        for s in (r..=max).rev() {
            counts[s] += counts[s - r];
        }
    }
    let total: f64 = counts.iter().sum();
    counts[w.min(max + 1)..].iter().sum::<f64>() / total
}

/// P(Z > z) for a standard normal Z.
pub fn normal_upper_tail(z: f64) -> f64 {
    0.5 * erfc(z / std::f64::consts::SQRT_2)
}

/// Complementary error function: a Chebyshev-fitted exponential approximation with
/// fractional error below 1.2e-7 everywhere, ample for p-values.
fn erfc(x: f64) -> f64 {
    let z = x.abs();
    let t = 1.0 / (1.0 + 0.5 * z);
    let poly = -z * z - 1.265_512_23
        + t * (1.000_023_68
            + t * (0.374_091_96
                + t * (0.096_784_18
                    + t * (-0.186_288_06
                        + t * (0.278_868_07
                            + t * (-1.135_203_98
                                + t * (1.488_515_87 + t * (-0.822_152_23 + t * 0.170_872_77))))))));
    let r = t * poly.exp();
    if x >= 0.0 { r } else { 2.0 - r }
}

/// Random sign patterns drawn when there are too many runs to enumerate all of them.
const SIGN_FLIP_DRAWS: u64 = 200_000;
/// Up to this many runs every sign pattern is enumerated (2^16 patterns).
const SIGN_FLIP_EXACT_MAX_N: usize = 16;

/// One-sided p-value of the paired sign-flip (randomization) test on the sum of the
/// differences, for H1: they tend to be > 0. Under the null each difference is as likely
/// to have either sign, so the observed sum is compared with the sums under every sign
/// pattern (exactly up to 16 differences, else 200,000 patterns from a fixed seed).
/// Unlike the signed-rank test it weighs each run by how much it changed, so an effect
/// that shows strongly in a few runs (those off the nominal condition) is not outvoted by
/// many runs that change by noise; one large run alone still gives p near 1/2.
pub fn sign_flip_greater(differences: &[f64]) -> f64 {
    let d: Vec<f64> = differences
        .iter()
        .copied()
        .filter(|x| *x != 0.0 && x.is_finite())
        .collect();
    let n = d.len();
    if n == 0 {
        return 1.0;
    }
    let observed: f64 = d.iter().sum();
    // Sums within rounding of the observed one count as reaching it.
    let tolerance = 1e-12 * d.iter().map(|x| x.abs()).sum::<f64>();
    let reaches = |signs: u64| {
        let s: f64 = d
            .iter()
            .enumerate()
            .map(|(i, x)| {
                if signs >> (i % 64) & 1 == 1 {
                    -x.abs()
                } else {
                    x.abs()
                }
            })
            .sum();
        s >= observed - tolerance
    };
    if n <= SIGN_FLIP_EXACT_MAX_N {
        let patterns = 1u64 << n;
        let hits = (0..patterns).filter(|&s| reaches(s)).count();
        return hits as f64 / patterns as f64;
    }
    // splitmix64 stream; n > 64 reuses bits across differences, so draw per 64 differences.
    let mut state = 0x005e_ed0f_f11b_u64;
    let mut next = || {
        state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    };
    let mut hits = 0u64;
    for _ in 0..SIGN_FLIP_DRAWS {
        let words: Vec<u64> = (0..n.div_ceil(64)).map(|_| next()).collect();
        let s: f64 = d
            .iter()
            .enumerate()
            .map(|(i, x)| {
                if words[i / 64] >> (i % 64) & 1 == 1 {
                    -x.abs()
                } else {
                    x.abs()
                }
            })
            .sum();
        if s >= observed - tolerance {
            hits += 1;
        }
    }
    // The observed pattern counts as one of the draws (a valid Monte Carlo p-value).
    (hits + 1) as f64 / (SIGN_FLIP_DRAWS + 1) as f64
}

/// Fisher's combination of p-values of one hypothesis tested on several channels:
/// -2 sum ln p is chi-square with 2k degrees of freedom when the tests are independent.
/// (Channels measured in the same runs are not fully independent, so this leans liberal;
/// the diagnosis also demands a minimum gain.)
pub fn fisher_combined(p: &[f64]) -> f64 {
    if p.is_empty() {
        return 1.0;
    }
    let half_x: f64 = -p
        .iter()
        .map(|q| q.clamp(f64::MIN_POSITIVE, 1.0).ln())
        .sum::<f64>();
    // P(chi2_2k > x) = exp(-x/2) sum_{i<k} (x/2)^i / i!
    let (mut term, mut sum) = (1.0, 1.0);
    for i in 1..p.len() {
        term *= half_x / i as f64;
        sum += term;
    }
    ((-half_x).exp() * sum).min(1.0)
}

/// Holm-Bonferroni adjusted p-values (same order as the input).
pub fn holm(p: &[f64]) -> Vec<f64> {
    let m = p.len();
    let mut order: Vec<usize> = (0..m).collect();
    order.sort_by(|&a, &b| p[a].total_cmp(&p[b]));
    let mut adjusted = vec![1.0; m];
    let mut running = 0.0f64;
    for (k, &i) in order.iter().enumerate() {
        running = running.max(((m - k) as f64 * p[i]).min(1.0));
        adjusted[i] = running;
    }
    adjusted
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exact_distribution_matches_hand_counts() {
        // n = 3: sums 0..6 with counts 1,1,1,2,1,1,1 (8 patterns).
        assert!((exact_upper_tail(3, 6) - 1.0 / 8.0).abs() < 1e-15);
        assert!((exact_upper_tail(3, 3) - 5.0 / 8.0).abs() < 1e-15);
        assert_eq!(exact_upper_tail(3, 0), 1.0);
    }

    #[test]
    fn all_positive_differences_are_significant_and_symmetric_ones_are_not() {
        let up: Vec<f64> = (1..=12).map(|i| i as f64 * 0.1).collect();
        let p = wilcoxon_greater(&up);
        assert!((p - 1.0 / 4096.0).abs() < 1e-12, "{p}");
        let down: Vec<f64> = up.iter().map(|x| -x).collect();
        assert!(wilcoxon_greater(&down) > 0.999);
        let mixed: Vec<f64> = (1..=20)
            .map(|i| if i % 2 == 0 { i as f64 } else { -(i as f64) })
            .collect();
        let p = wilcoxon_greater(&mixed);
        assert!(p > 0.3 && p < 0.7, "{p}");
        assert_eq!(wilcoxon_greater(&[0.0, 0.0]), 1.0);
    }

    #[test]
    fn normal_approximation_agrees_with_exact_for_moderate_n() {
        // 30 differences, ranks 1..30, positive for the top 20: compare both routes.
        let d: Vec<f64> = (1..=30)
            .map(|i| if i > 10 { i as f64 } else { -(i as f64) })
            .collect();
        let exact = wilcoxon_greater(&d);
        let n = 30.0;
        let w: f64 = (11..=30).sum::<i32>() as f64;
        let z =
            (w - n * (n + 1.0) / 4.0 - 0.5) / (n * (n + 1.0) * (2.0 * n + 1.0) / 24.0f64).sqrt();
        assert!(
            (exact - normal_upper_tail(z)).abs() < 2e-3,
            "{exact} vs {}",
            normal_upper_tail(z)
        );
        assert!((normal_upper_tail(1.959_964) - 0.025).abs() < 1e-6);
        assert!((normal_upper_tail(0.0) - 0.5).abs() < 1e-7);
    }

    #[test]
    fn sign_flip_counts_patterns_exactly_and_weighs_magnitudes() {
        // Three positive differences: only the all-positive pattern reaches the sum.
        assert!((sign_flip_greater(&[1.0, 2.0, 3.0]) - 1.0 / 8.0).abs() < 1e-15);
        // {3, -1, -1}: sums >= 1 are (3,1,1)=5, (3,-1,1)=3, (3,1,-1)=3, (3,-1,-1)=1: 4 of 8.
        assert!((sign_flip_greater(&[3.0, -1.0, -1.0]) - 0.5).abs() < 1e-15);
        // A few large gains among many small losses: significant here, not for signed ranks.
        // (p is bounded below by 2^-10: only the ten large runs carry the sum.)
        let mut d = vec![-0.1; 24];
        d.extend((5..15).map(f64::from));
        let p = sign_flip_greater(&d);
        assert!(p < 0.002, "{p}");
        assert!(wilcoxon_greater(&d) > 0.05);
        // One huge gain alone is not evidence.
        let mut one = vec![-0.1; 29];
        one.push(100.0);
        let p = sign_flip_greater(&one);
        assert!(p > 0.4 && p < 0.6, "{p}");
        // Monte Carlo route agrees with the exact one where both apply in distribution:
        // 20 equal gains and 10 equal losses: P(sum >= 10) for 30 fair signs = P(K >= 20).
        let mut d: Vec<f64> = vec![1.0; 20];
        d.extend(vec![-1.0; 10]);
        let exact: f64 = (20..=30u32)
            .map(|k| (0..k).fold(1.0, |c, i| c * (30 - i) as f64 / (i + 1) as f64))
            .sum::<f64>()
            / 2f64.powi(30);
        let p = sign_flip_greater(&d);
        assert!((p - exact).abs() < 0.003, "{p} vs {exact}");
        assert_eq!(sign_flip_greater(&[]), 1.0);
    }

    #[test]
    fn fisher_combination_matches_chi_square_tails() {
        // One p-value is returned unchanged.
        assert!((fisher_combined(&[0.03]) - 0.03).abs() < 1e-12);
        // Two: x = -2 ln(0.1 * 0.2) = 7.824; P(chi2_4 > x) = e^{-x/2} (1 + x/2) = 0.0982.
        let x: f64 = -2.0 * (0.1f64 * 0.2).ln();
        let want = (-x / 2.0).exp() * (1.0 + x / 2.0);
        assert!((fisher_combined(&[0.1, 0.2]) - want).abs() < 1e-12);
        assert!((want - 0.0982).abs() < 1e-3);
        // Channels with no evidence (p = 1) dilute but do not cancel strong evidence.
        assert!(fisher_combined(&[1e-6, 1.0, 1.0]) < 1e-3);
        assert_eq!(fisher_combined(&[1.0, 1.0]), 1.0);
        assert_eq!(fisher_combined(&[]), 1.0);
    }

    #[test]
    fn holm_adjusts_in_step_down_order() {
        let adj = holm(&[0.01, 0.04, 0.03, 0.5]);
        assert!((adj[0] - 0.04).abs() < 1e-12);
        assert!((adj[2] - 0.09).abs() < 1e-12);
        assert!((adj[1] - 0.09).abs() < 1e-12);
        assert!((adj[3] - 0.5).abs() < 1e-12);
    }
}
