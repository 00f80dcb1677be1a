//! Summaries of a series (mean square, correlation; the median and quantiles are in
//! [`crate::quantiles`]) and significance: the
//! one-sided paired sign-flip (randomization) test on per-run differences, Fisher's and
//! Bonferroni's combination over channels, and Holm's correction over candidates.

use std::sync::Arc;

use crate::method::splitmix::splitmix64;

/// Held-out residuals kept at single precision: 7 significant digits, finer than any force or
/// moment measurement. A diagnosis holds several series (each channel's current model per
/// assignment of folds, the candidates being scored), each as long as the data, so the full 8
/// bytes per row would dominate a large diagnosis's memory. Clones share one allocation.
#[derive(Debug, Clone, PartialEq)]
pub struct CompactResiduals(Arc<[f32]>);

impl CompactResiduals {
    pub fn new(residuals: &[f64]) -> Self {
        CompactResiduals(residuals.iter().map(|r| *r as f32).collect())
    }

    /// Residuals already in single precision.
    pub fn from_single(residuals: Vec<f32>) -> Self {
        CompactResiduals(residuals.into())
    }

    /// The values as stored.
    pub fn as_single(&self) -> &[f32] {
        &self.0
    }

    pub fn len(&self) -> usize {
        self.0.len()
    }

    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    /// Row `i`'s residual.
    pub fn get(&self, i: usize) -> f64 {
        f64::from(self.0[i])
    }

    pub fn iter(&self) -> impl Iterator<Item = f64> + '_ {
        self.0.iter().map(|r| f64::from(*r))
    }

    pub fn to_vec(&self) -> Vec<f64> {
        self.iter().collect()
    }

    /// [`mse`] of the values as doubles.
    pub fn mse(&self) -> f64 {
        let (sum, n) = self
            .iter()
            .filter(|r| r.is_finite())
            .fold((0.0, 0usize), |(s, n), r| (s + r * r, n + 1));
        sum / n.max(1) as f64
    }
}

/// The mean square of the finite values (0 when there is none).
pub fn mse(residuals: &[f64]) -> f64 {
    mean_square(residuals.iter().copied())
}

/// The mean square of the finite `values` (0 without any), summed in their order.
pub fn mean_square(values: impl Iterator<Item = f64>) -> f64 {
    let (sum, n) = values
        .filter(|r| r.is_finite())
        .fold((0.0, 0usize), |(s, n), r| (s + r * r, n + 1));
    sum / n.max(1) as f64
}

/// The mean of the finite `values` (NaN without any).
pub fn mean(values: impl Iterator<Item = f64>) -> f64 {
    let (sum, n) = values
        .filter(|v| v.is_finite())
        .fold((0.0, 0usize), |(s, n), v| (s + v, n + 1));
    match n {
        0 => f64::NAN,
        n => sum / n as f64,
    }
}

/// Pearson's correlation of two series of equal length; `None` below three values or when
/// either is constant.
pub fn correlation(a: &[f64], b: &[f64]) -> Option<f64> {
    let n = a.len().min(b.len());
    if n < 3 {
        return None;
    }
    let (ma, mb) = (
        a.iter().sum::<f64>() / n as f64,
        b.iter().sum::<f64>() / n as f64,
    );
    let (mut sab, mut saa, mut sbb) = (0.0, 0.0, 0.0);
    for i in 0..n {
        let (x, y) = (a[i] - ma, b[i] - mb);
        sab += x * y;
        saa += x * x;
        sbb += y * y;
    }
    (saa > 0.0 && sbb > 0.0).then(|| sab / (saa * sbb).sqrt())
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
    let magnitudes: Vec<f64> = d.iter().map(|x| x.abs()).collect();
    let total: f64 = magnitudes.iter().sum();
    // Sums within rounding of the observed one count as reaching it.
    let threshold = observed - 1e-12 * total;
    if n <= SIGN_FLIP_EXACT_MAX_N {
        let patterns = 1u64 << n;
        let hits = (0..patterns)
            .filter(|&bits| {
                let negated: f64 = (0..n)
                    .filter(|i| bits >> i & 1 == 1)
                    .map(|i| magnitudes[i])
                    .sum();
                total - 2.0 * negated >= threshold
            })
            .count();
        return hits as f64 / patterns as f64;
    }
    // Bit i of word i / 64 of a draw negates difference i. The sum of the negated magnitudes
    // is read a byte at a time from the sums of every subset of each 8 differences (group g:
    // byte g % 8 of word g / 8), so a draw costs n / 8 table reads, not a branch per
    // difference. The draws go in blocks, one group at a time for the whole block: each
    // group's table stays in cache and the block's sums are independent of each other.
    let groups = n.div_ceil(8);
    let mut subset_sums = vec![0.0; groups * 256];
    for (g, sums) in subset_sums.chunks_exact_mut(256).enumerate() {
        let group = &magnitudes[8 * g..(8 * g + 8).min(n)];
        for (byte, sum) in sums.iter_mut().enumerate() {
            *sum = group
                .iter()
                .enumerate()
                .filter(|(j, _)| byte >> j & 1 == 1)
                .map(|(_, m)| m)
                .sum();
        }
    }
    const BLOCK: usize = 256;
    let words_per_draw = n.div_ceil(64);
    // words[w * BLOCK + d]: word w of draw d of the block, drawn in the order draw by draw,
    // word by word, from the split's generator (bits past the last difference select nothing).
    let mut words = vec![0u64; words_per_draw * BLOCK];
    let mut negated = [0.0f64; BLOCK];
    let mut state = 0x005e_ed0f_f11b_u64;
    let mut hits = 0u64;
    let mut left = SIGN_FLIP_DRAWS as usize;
    while left > 0 {
        let block = left.min(BLOCK);
        left -= block;
        for d in 0..block {
            for w in 0..words_per_draw {
                words[w * BLOCK + d] = splitmix64(&mut state);
            }
        }
        negated[..block].fill(0.0);
        for (g, sums) in subset_sums.chunks_exact(256).enumerate() {
            let (w, shift) = (g / 8, 8 * (g % 8));
            let word = &words[w * BLOCK..w * BLOCK + block];
            for (sum, bits) in negated.iter_mut().zip(word) {
                *sum += sums[(bits >> shift & 0xff) as usize];
            }
        }
        hits += negated[..block]
            .iter()
            .filter(|&&x| total - 2.0 * x >= threshold)
            .count() as u64;
    }
    // The observed pattern counts as one of the draws (a valid Monte Carlo p-value).
    (hits + 1) as f64 / (SIGN_FLIP_DRAWS + 1) as f64
}

/// Pairings drawn by [`permutation_trend`] when there are too many to enumerate.
const PERMUTATION_DRAWS: u64 = 20_000;
/// Up to this many pairs, [`permutation_trend`] enumerates every pairing (8! = 40,320).
const PERMUTATION_EXACT_MAX_N: usize = 8;
/// Beyond this many pairs, [`permutation_trend`] takes the normal distribution with the
/// permutation distribution's own mean and variance (exact moments; the sum of many pairs'
/// products is near normal), instead of drawing.
const PERMUTATION_NORMAL_MIN_N: usize = 400;

/// One-sided p-value of the permutation test of a rising trend of `y` with `x`, for H1: larger
/// `x` go with larger `y`. Under the null the pairing of the `x` and the `y` is exchangeable,
/// so the observed sum of products `sum x_i y_i` is compared with its value under every
/// re-pairing (exactly up to 8 pairs, else 20,000 drawn from a fixed seed with the observed
/// one counted as a draw, and beyond 400 pairs by the normal law with the permutation
/// distribution's mean and variance). With `x` 1 in one sample and 0 in the other it is the
/// two-sample test of a difference of means. Pairs with a non-finite value are left out; 1
/// with fewer than two pairs or a constant `x` or `y`.
pub fn permutation_trend(x: &[f64], y: &[f64]) -> f64 {
    let (x, y): (Vec<f64>, Vec<f64>) = x
        .iter()
        .zip(y)
        .filter(|(a, b)| a.is_finite() && b.is_finite())
        .map(|(a, b)| (*a, *b))
        .unzip();
    let n = x.len();
    let mean = |v: &[f64]| v.iter().sum::<f64>() / n.max(1) as f64;
    // Centred, so that the sums compared are the covariance's and rounding stays small.
    let (mx, my) = (mean(&x), mean(&y));
    let x: Vec<f64> = x.iter().map(|a| a - mx).collect();
    let y: Vec<f64> = y.iter().map(|b| b - my).collect();
    let (sxx, syy) = (
        x.iter().map(|a| a * a).sum::<f64>(),
        y.iter().map(|b| b * b).sum::<f64>(),
    );
    if n < 2 || sxx <= 0.0 || syy <= 0.0 {
        return 1.0;
    }
    let product = |order: &[usize]| -> f64 { x.iter().zip(order).map(|(a, &k)| a * y[k]).sum() };
    let identity: Vec<usize> = (0..n).collect();
    let observed = product(&identity);
    // Sums within rounding of the observed one count as reaching it.
    let threshold = observed - 1e-9 * (sxx * syy).sqrt();
    if n > PERMUTATION_NORMAL_MIN_N {
        // Mean 0 (centred); variance sxx syy / (n - 1).
        let sd = (sxx * syy / (n - 1) as f64).sqrt();
        return normal_upper(threshold / sd);
    }
    if n <= PERMUTATION_EXACT_MAX_N {
        let (mut hits, mut all) = (0u64, 0u64);
        for_each_permutation(n, |order| {
            all += 1;
            if product(order) >= threshold {
                hits += 1;
            }
        });
        return hits as f64 / all as f64;
    }
    let mut state = 0x0000_051a_7ed5_eed5_u64;
    let mut order = identity;
    let mut hits = 0u64;
    for _ in 0..PERMUTATION_DRAWS {
        for i in (1..n).rev() {
            let j = (splitmix64(&mut state) % (i + 1) as u64) as usize;
            order.swap(i, j);
        }
        if product(&order) >= threshold {
            hits += 1;
        }
    }
    (hits + 1) as f64 / (PERMUTATION_DRAWS + 1) as f64
}

/// The ranks of `v` from 0, ties at their mean rank (non-finite values rank NaN).
pub fn ranks(v: &[f64]) -> Vec<f64> {
    let mut order: Vec<usize> = (0..v.len()).filter(|&i| v[i].is_finite()).collect();
    order.sort_by(|&a, &b| v[a].total_cmp(&v[b]));
    let mut out = vec![f64::NAN; v.len()];
    let mut k = 0;
    while k < order.len() {
        let tied = order[k..]
            .iter()
            .take_while(|&&i| v[i] == v[order[k]])
            .count();
        let mean = k as f64 + (tied - 1) as f64 / 2.0;
        for &i in &order[k..k + tied] {
            out[i] = mean;
        }
        k += tied;
    }
    out
}

/// Calls `f` with every ordering of `0..n` (Heap's algorithm, iterative).
fn for_each_permutation(n: usize, mut f: impl FnMut(&[usize])) {
    let mut order: Vec<usize> = (0..n).collect();
    let mut counters = vec![0usize; n];
    f(&order);
    let mut i = 1;
    while i < n {
        if counters[i] < i {
            let j = if i % 2 == 0 { 0 } else { counters[i] };
            order.swap(j, i);
            f(&order);
            counters[i] += 1;
            i = 1;
        } else {
            counters[i] = 0;
            i += 1;
        }
    }
}

/// The upper tail of the standard normal distribution, `P(Z > z)`, from the complementary
/// error function's Chebyshev fit (relative error below 1.2e-7 everywhere).
pub fn normal_upper(z: f64) -> f64 {
    let x = z / std::f64::consts::SQRT_2;
    let t = 1.0 / (1.0 + 0.5 * x.abs());
    let poly = -x * x - 1.265_512_23
        + t * (1.000_023_68
            + t * (0.374_091_96
                + t * (0.096_784_18
                    + t * (-0.186_288_06
                        + t * (0.278_868_07
                            + t * (-1.135_203_98
                                + t * (1.488_515_87 + t * (-0.822_152_23 + t * 0.170_872_77))))))));
    let erfc = t * poly.exp();
    let upper = 0.5 * erfc;
    if x >= 0.0 { upper } else { 1.0 - upper }
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

/// One p-value for an effect tested on several channels. Fisher's method is strong when the
/// effect shows on most channels, but a channel the effect does not touch dilutes it; the
/// smallest p-value times the number of channels (Bonferroni) is strong when it shows on one
/// channel only. The better of the two, doubled for having looked twice.
pub fn channels_combined(p: &[f64]) -> f64 {
    match p {
        [] => 1.0,
        [only] => only.clamp(0.0, 1.0),
        _ => {
            let smallest = p.iter().copied().fold(1.0, f64::min);
            let bonferroni = p.len() as f64 * smallest;
            (2.0 * fisher_combined(p).min(bonferroni)).min(1.0)
        }
    }
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
    #[test]
    fn compact_residuals_keep_seven_digits_and_missing_rows() {
        let r = [1234.5678, -0.001_234_567, f64::NAN, 0.0];
        let back = CompactResiduals::new(&r).to_vec();
        for (a, b) in r.iter().zip(&back) {
            if a.is_nan() {
                assert!(b.is_nan());
            } else {
                assert!((a - b).abs() <= 1e-7 * a.abs(), "{a} {b}");
            }
        }
    }

    use super::*;

    #[test]
    fn permutation_trend_by_worked_values() {
        // Two samples as x = 1 and x = 0: a = {3, 4}, b = {1, 2}. Of the 24 pairings, those
        // that put {3, 4} on the ones (4 of 24) reach the observed sum: p = 1/6. Reversed, every
        // pairing reaches it: p = 1.
        let x = [1.0, 1.0, 0.0, 0.0];
        assert!((permutation_trend(&x, &[3.0, 4.0, 1.0, 2.0]) - 1.0 / 6.0).abs() < 1e-12);
        assert_eq!(permutation_trend(&x, &[1.0, 2.0, 3.0, 4.0]), 1.0);
        // A perfect rise of three: only the identity (1 of 6) reaches it.
        assert!(
            (permutation_trend(&[1.0, 2.0, 3.0], &[10.0, 20.0, 40.0]) - 1.0 / 6.0).abs() < 1e-12
        );
        // Ties count as reaching: x = {1, 0, 0}, y = {2, 2, 1}: two of three places for the 1.
        assert!((permutation_trend(&[1.0, 0.0, 0.0], &[2.0, 2.0, 1.0]) - 2.0 / 3.0).abs() < 1e-12);
        assert_eq!(permutation_trend(&[1.0], &[1.0]), 1.0);
        assert_eq!(permutation_trend(&[1.0, 1.0, 1.0], &[1.0, 2.0, 3.0]), 1.0);
        assert_eq!(
            permutation_trend(&[1.0, f64::NAN, 0.0], &[2.0, 5.0, 1.0]),
            0.5
        );
    }

    #[test]
    fn permutation_trend_holds_its_level_when_drawing_and_in_the_normal_law() {
        let mut state = 7u64;
        let mut u = || (splitmix64(&mut state) >> 11) as f64 / (1u64 << 53) as f64;
        for n in [40, 600] {
            // Unrelated x and y: about 5 % of the p-values fall below 0.05.
            let mut below = 0;
            for _ in 0..200 {
                let x: Vec<f64> = (0..n).map(|_| u()).collect();
                let y: Vec<f64> = (0..n).map(|_| u()).collect();
                if permutation_trend(&x, &y) < 0.05 {
                    below += 1;
                }
            }
            assert!(
                (3..=20).contains(&below),
                "n {n}: {below} of 200 below 0.05"
            );
            // y rising with x as much as it scatters (a correlation of 0.7) is found.
            let x: Vec<f64> = (0..n).map(|_| u()).collect();
            let y: Vec<f64> = x.iter().map(|a| a + u()).collect();
            assert!(permutation_trend(&x, &y) < 0.01, "n {n}");
        }
    }

    #[test]
    fn ranks_share_ties() {
        let r = ranks(&[3.0, 1.0, 3.0, f64::NAN, 2.0]);
        assert_eq!(&r[..3], &[2.5, 0.0, 2.5]);
        assert!(r[3].is_nan());
        assert_eq!(r[4], 1.0);
    }

    #[test]
    fn the_normal_upper_tail_by_its_tabled_values() {
        for (z, p) in [
            (0.0, 0.5),
            (1.0, 0.158_655_25),
            (1.644_853_6, 0.05),
            (-2.0, 0.977_249_87),
            (3.0, 0.001_349_898),
        ] {
            assert!(
                (normal_upper(z) - p).abs() < 2e-7 * p.max(1e-3),
                "{z}: {}",
                normal_upper(z)
            );
        }
    }

    #[test]
    fn mean_square_skips_non_finite_values() {
        // (1 + 4 + 9) / 3 = 14 / 3; the NaN is not counted.
        assert_eq!(mse(&[1.0, -2.0, f64::NAN, 3.0]), 14.0 / 3.0);
        assert_eq!(mse(&[f64::NAN]), 0.0);
        assert_eq!(mse(&[]), 0.0);
    }

    #[test]
    fn correlation_by_worked_values() {
        // a = 1, 2, 3, 4 and b = 2, 1, 4, 3: means 2.5, deviations (-1.5, -0.5, 0.5, 1.5) and
        // (-0.5, -1.5, 1.5, 0.5); sum of products 0.75 + 0.75 + 0.75 + 0.75 = 3, sums of
        // squares 5 and 5: r = 3 / sqrt(5 * 5) = 0.6.
        let r = correlation(&[1.0, 2.0, 3.0, 4.0], &[2.0, 1.0, 4.0, 3.0]).unwrap();
        assert!((r - 0.6).abs() < 1e-15, "{r}");
        // Perfectly opposite: -1.
        let r = correlation(&[1.0, 2.0, 3.0], &[3.0, 2.0, 1.0]).unwrap();
        assert!((r + 1.0).abs() < 1e-15, "{r}");
        // Too short, or a constant series: none.
        assert_eq!(correlation(&[1.0, 2.0], &[2.0, 1.0]), None);
        assert_eq!(correlation(&[1.0, 2.0, 3.0], &[1.0, 1.0, 1.0]), None);
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
    fn sign_flip_draws_sum_as_the_differences_one_by_one() {
        // Many runs of uneven gains, and counts that are not a multiple of 8 or 64: the
        // byte-table sums reach the observed sum in exactly the draws a difference-by-
        // difference sum does.
        let mut state = 7u64;
        for n in [17usize, 71, 300] {
            let d: Vec<f64> = (0..n)
                .map(|_| (splitmix64(&mut state) % 2000) as f64 / 1000.0 - 0.8)
                .collect();
            let observed: f64 = d.iter().sum();
            let total: f64 = d.iter().map(|x| x.abs()).sum();
            let mut draws = 0x005e_ed0f_f11b_u64;
            let mut words = vec![0u64; n.div_ceil(64)];
            let mut hits = 0u64;
            for _ in 0..SIGN_FLIP_DRAWS {
                for w in &mut words {
                    *w = splitmix64(&mut draws);
                }
                let negated: f64 = (0..n)
                    .filter(|i| words[i / 64] >> (i % 64) & 1 == 1)
                    .map(|i| d[i].abs())
                    .sum();
                hits += u64::from(total - 2.0 * negated >= observed - 1e-12 * total);
            }
            let want = (hits + 1) as f64 / (SIGN_FLIP_DRAWS + 1) as f64;
            assert_eq!(sign_flip_greater(&d), want, "{n} runs");
        }
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
    fn channel_combination_takes_the_stronger_method_at_twice_its_p() {
        // One channel: its own p-value.
        assert_eq!(channels_combined(&[0.03]), 0.03);
        assert_eq!(channels_combined(&[]), 1.0);
        // Evidence on one channel of three: Fisher gives 0.0135 (x/2 = 8.0235,
        // e^{-x/2} (1 + x/2 + (x/2)^2 / 2) = 0.01351); Bonferroni 3 * 7.9e-4 = 2.37e-3 wins.
        let one = [0.61, 7.9e-4, 0.68];
        assert!((fisher_combined(&one) - 0.01351).abs() < 1e-4);
        assert!((channels_combined(&one) - 2.0 * 3.0 * 7.9e-4).abs() < 1e-12);
        // Moderate evidence on every channel: Fisher (0.0175) beats Bonferroni (0.06).
        let all = [0.02, 0.03, 0.04];
        let fisher = fisher_combined(&all);
        assert!(fisher < 0.06);
        assert!((channels_combined(&all) - 2.0 * fisher).abs() < 1e-12);
        // Never above 1.
        assert_eq!(channels_combined(&[0.9, 0.8]), 1.0);
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
