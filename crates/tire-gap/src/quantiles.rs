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

/// The `k`-th smallest of `v` (from 0, in `f64::total_cmp` order), as sorting would put it
/// at position `k`, found in linear time; `v` is reordered around it.
pub fn order_statistic(v: &mut [f64], k: usize) -> f64 {
    *v.select_nth_unstable_by(k, f64::total_cmp).1
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
