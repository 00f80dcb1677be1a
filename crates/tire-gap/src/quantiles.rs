//! Order statistics of a series, which the readers and the method share: quantiles and the
//! median.

/// The `q`-quantile (0..=1) of the finite values, by linear interpolation between order
/// statistics; `None` when there is none.
pub fn quantile(values: &[f64], q: f64) -> Option<f64> {
    let mut v: Vec<f64> = values.iter().copied().filter(|x| x.is_finite()).collect();
    if v.is_empty() {
        return None;
    }
    let pos = q.clamp(0.0, 1.0) * (v.len() - 1) as f64;
    let (i, frac) = (pos.floor() as usize, pos.fract());
    let at = order_statistic(&mut v, i);
    // The next order statistic is the least of those above position i.
    let next = v[i + 1..]
        .iter()
        .copied()
        .min_by(f64::total_cmp)
        .unwrap_or(at);
    Some(at + frac * (next - at))
}

/// [`quantile`] of the finite values that `values()` yields, without a copy of them (see
/// [`order_statistic_of`]): the same value to the bit.
pub fn quantile_of<I: Iterator<Item = f64>>(values: impl Fn() -> I, q: f64) -> Option<f64> {
    let n = values().filter(|x| x.is_finite()).count();
    if n == 0 {
        return None;
    }
    let pos = q.clamp(0.0, 1.0) * (n - 1) as f64;
    let (i, frac) = (pos.floor() as usize, pos.fract());
    let at = order_statistic_of(&values, i)?;
    let next = match i + 1 < n {
        true => order_statistic_of(&values, i + 1)?,
        false => at,
    };
    Some(at + frac * (next - at))
}

/// The `k`-th smallest of `v` (from 0, in `f64::total_cmp` order), as sorting would put it
/// at position `k`, found in linear time; `v` is reordered around it.
pub fn order_statistic(v: &mut [f64], k: usize) -> f64 {
    *v.select_nth_unstable_by(k, f64::total_cmp).1
}

/// The `k`-th smallest (from 0, in `f64::total_cmp` order) of the finite values that
/// `values()` yields, as [`order_statistic`] of them would find it, without a copy of them:
/// a radix selection on the bits of the values, 16 bits a pass over `values()`,
/// until at most `GATHERED_MAX` (2^20) values can still be the one, which are then gathered.
/// `None` when there are no more than `k` finite values.
pub fn order_statistic_of<I: Iterator<Item = f64>>(
    values: impl Fn() -> I,
    k: usize,
) -> Option<f64> {
    radix_select(values, k, GATHERED_MAX)
}

/// [`order_statistic_of`], gathering the candidates once at most `gathered_max` are left.
fn radix_select<I: Iterator<Item = f64>>(
    values: impl Fn() -> I,
    k: usize,
    gathered_max: usize,
) -> Option<f64> {
    let finite = || values().filter(|x| x.is_finite());
    let (mut k, mut known, mut prefix) = (k, 0u32, 0u64);
    let shares_prefix = |key: u64, known: u32, prefix: u64| {
        known == 0 || key >> (64 - known) == prefix >> (64 - known)
    };
    loop {
        let shift = 64 - known - RADIX_BITS;
        let mut counts = vec![0usize; 1 << RADIX_BITS];
        for key in finite().map(total_order_key) {
            if shares_prefix(key, known, prefix) {
                counts[((key >> shift) & ((1 << RADIX_BITS) - 1)) as usize] += 1;
            }
        }
        // The first pass counts every finite value.
        if known == 0 && counts.iter().sum::<usize>() <= k {
            return None;
        }
        let mut bucket = 0;
        while k >= counts[bucket] {
            k -= counts[bucket];
            bucket += 1;
        }
        prefix |= (bucket as u64) << shift;
        known += RADIX_BITS;
        if known == 64 {
            return Some(from_total_order_key(prefix));
        }
        if counts[bucket] <= gathered_max {
            let mut left: Vec<f64> = finite()
                .filter(|x| shares_prefix(total_order_key(*x), known, prefix))
                .collect();
            return Some(order_statistic(&mut left, k));
        }
    }
}

/// Bits of a value's key that one pass of [`order_statistic_of`] sorts on (a divisor of 64).
const RADIX_BITS: u32 = 16;
/// Candidates few enough for [`order_statistic_of`] to gather and select among.
const GATHERED_MAX: usize = 1 << 20;

/// A key whose unsigned order is `f64::total_cmp`'s: the sign bit set for positive values,
/// every bit flipped for negative ones.
fn total_order_key(x: f64) -> u64 {
    let bits = x.to_bits();
    match bits >> 63 {
        1 => !bits,
        _ => bits | 1 << 63,
    }
}

/// The value of a [`total_order_key`].
fn from_total_order_key(key: u64) -> f64 {
    f64::from_bits(match key >> 63 {
        1 => key & !(1 << 63),
        _ => !key,
    })
}

/// The median of the finite values; `None` when there is none. For an even number of values
/// it is the upper of the two middle ones, so it is always one of the values (a measured
/// level, not a midpoint between two), and it is negative exactly when more than half of the
/// values are: the readers' test of a load channel that is mostly negative.
pub fn median(v: &[f64]) -> Option<f64> {
    let mut s: Vec<f64> = v.iter().copied().filter(|x| x.is_finite()).collect();
    if s.is_empty() {
        return None;
    }
    let middle = s.len() / 2;
    Some(order_statistic(&mut s, middle))
}

/// [`median`] of the finite values that `values()` yields, without a copy of them (see
/// [`order_statistic_of`]).
pub fn median_of<I: Iterator<Item = f64>>(values: impl Fn() -> I) -> Option<f64> {
    let n = values().filter(|x| x.is_finite()).count();
    order_statistic_of(values, n / 2)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantiles_interpolate_and_skip_non_finite() {
        let v = [4.0, f64::NAN, 1.0, 3.0, 2.0];
        assert_eq!(quantile(&v, 0.0), Some(1.0));
        assert_eq!(quantile(&v, 1.0), Some(4.0));
        assert_eq!(quantile(&v, 0.5), Some(2.5));
        assert_eq!(quantile(&[f64::NAN], 0.5), None);
    }

    #[test]
    fn an_order_statistic_of_a_stream_is_the_one_of_its_copy() {
        // Values with ties, both zeros, negatives, non-finite ones, and a cluster of tens of
        // thousands within one bucket of the first pass (to be told apart by later passes).
        let mut v: Vec<f64> = (0..400_000)
            .map(|i: i32| {
                let x = ((i as f64) * 0.618_033_988_75).fract();
                match i % 11 {
                    0 => f64::NAN,
                    1 => -0.0,
                    2 => 0.0,
                    3 => 4.0 + 1e-9 * x,
                    4 => f64::INFINITY,
                    5 => 4.0,
                    _ => 1e3 * (x - 0.4),
                }
            })
            .collect();
        v.push(f64::NEG_INFINITY);
        let finite: Vec<f64> = v.iter().copied().filter(|x| x.is_finite()).collect();
        let near_four = finite.iter().filter(|x| (**x - 4.0).abs() < 1e-6).count();
        // Gathering late, after the passes that tell the cluster's values apart.
        let gathered_max = 1000;
        assert!(near_four > 50 * gathered_max, "{near_four}");
        for k in [
            0,
            1,
            17,
            finite.len() / 3,
            finite.len() / 2,
            finite.len() - 1,
        ] {
            let mut copy = finite.clone();
            let expected = order_statistic(&mut copy, k);
            let got = order_statistic_of(|| v.iter().copied(), k).unwrap();
            assert_eq!(got.to_bits(), expected.to_bits(), "k = {k}");
            let late = radix_select(|| v.iter().copied(), k, gathered_max).unwrap();
            assert_eq!(
                late.to_bits(),
                expected.to_bits(),
                "k = {k}, gathering late"
            );
        }
        assert_eq!(order_statistic_of(|| v.iter().copied(), finite.len()), None);
        assert_eq!(order_statistic_of(|| [f64::NAN].into_iter(), 0), None);
        // Every key maps back to its value, in total_cmp's order.
        for x in [-1.5, -0.0, 0.0, 2.5e-300, f64::MAX, f64::MIN] {
            assert_eq!(
                from_total_order_key(total_order_key(x)).to_bits(),
                x.to_bits()
            );
        }
        assert!(total_order_key(-0.0) < total_order_key(0.0));
        assert!(total_order_key(-2.0) < total_order_key(-1.0));
    }

    #[test]
    fn a_quantile_of_a_stream_is_the_one_of_its_copy() {
        let v: Vec<f64> = (0..5000)
            .map(|i: i32| match i % 97 {
                0 => f64::NAN,
                k => (i as f64 * 0.37).sin() * k as f64,
            })
            .collect();
        for q in [0.0, 0.01, 0.25, 0.5, 0.9, 0.99, 1.0] {
            let got = quantile_of(|| v.iter().copied(), q).map(f64::to_bits);
            assert_eq!(got, quantile(&v, q).map(f64::to_bits), "q = {q}");
        }
        assert_eq!(quantile_of(|| [3.5].into_iter(), 0.7), Some(3.5));
        let median_bits = median_of(|| v.iter().copied()).map(f64::to_bits);
        assert_eq!(median_bits, median(&v).map(f64::to_bits));
        assert_eq!(median_of(|| [1.0, -3.0].into_iter()), Some(1.0));
        assert_eq!(median_of(std::iter::empty), None);
        assert_eq!(quantile_of(|| [f64::NAN].into_iter(), 0.5), None);
    }

    #[test]
    fn median_takes_the_upper_middle_of_the_finite_values() {
        // Finite values sorted: 1, 2, 3, 4; the upper of the middle two (index 4 / 2 = 2) is 3.
        assert_eq!(median(&[4.0, f64::NAN, 1.0, 3.0, 2.0]), Some(3.0));
        assert_eq!(median(&[5.0, f64::INFINITY, 1.0, 3.0]), Some(3.0));
        assert_eq!(median(&[f64::NAN]), None);
        assert_eq!(median(&[]), None);
        // Negative exactly when more than half the values are: sorted -3, -2, -1, 1 gives -1;
        // sorted -3, 1 gives 1 (half is not more than half).
        assert_eq!(median(&[1.0, -1.0, -3.0, -2.0]), Some(-1.0));
        assert_eq!(median(&[1.0, -3.0]), Some(1.0));
    }
}
