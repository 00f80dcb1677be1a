//! Binned means for the figures: of a residual over one input (with its standard error) and
//! over a grid of two inputs.

/// The rows whose input falls in one bin `[lo, hi)` (the last bin also holds `hi`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bin {
    pub lo: f64,
    pub hi: f64,
    pub count: usize,
    /// Mean of the input over the bin's rows (a better x than the centre for clustered data).
    pub x_mean: f64,
    pub mean: f64,
    /// Sample standard deviation / sqrt(count); NaN below two rows.
    pub std_err: f64,
}

/// `count` equal-width bins from `lo` to `hi`: `count + 1` edges.
pub fn edges(lo: f64, hi: f64, count: usize) -> Vec<f64> {
    let count = count.max(1);
    (0..=count)
        .map(|i| lo + (hi - lo) * i as f64 / count as f64)
        .collect()
}

/// The bin of `v` given ascending `edges`, or `None` outside them (or for NaN).
pub fn bin_index(edges: &[f64], v: f64) -> Option<usize> {
    let (first, last) = (*edges.first()?, *edges.last()?);
    if edges.len() < 2 || !(v >= first && v <= last) {
        return None;
    }
    // Index of the first edge above v, minus one; v == last goes to the last bin.
    let above = edges.partition_point(|e| *e <= v);
    Some(above.saturating_sub(1).min(edges.len() - 2))
}

/// Mean and standard error of `y` in each bin of `x`. Rows where either is not finite are
/// left out; every bin is returned, empty ones with count 0 and NaN statistics.
pub fn binned_means(x: &[f64], y: &[f64], edges: &[f64]) -> Vec<Bin> {
    let bins = edges.len().saturating_sub(1);
    let mut members: Vec<Vec<(f64, f64)>> = vec![Vec::new(); bins];
    for (&xi, &yi) in x.iter().zip(y) {
        if !yi.is_finite() {
            continue;
        }
        if let Some(b) = bin_index(edges, xi) {
            members[b].push((xi, yi));
        }
    }
    members
        .iter()
        .enumerate()
        .map(|(b, rows)| {
            let n = rows.len();
            let mean_of = |f: fn(&(f64, f64)) -> f64| rows.iter().map(f).sum::<f64>() / n as f64;
            let (x_mean, mean) = if n == 0 {
                (f64::NAN, f64::NAN)
            } else {
                (mean_of(|r| r.0), mean_of(|r| r.1))
            };
            let std_err = if n < 2 {
                f64::NAN
            } else {
                let ss: f64 = rows.iter().map(|r| (r.1 - mean).powi(2)).sum();
                (ss / (n - 1) as f64).sqrt() / (n as f64).sqrt()
            };
            Bin {
                lo: edges[b],
                hi: edges[b + 1],
                count: n,
                x_mean,
                mean,
                std_err,
            }
        })
        .collect()
}

/// Row count and mean of `z` in each cell of a grid over `x` and `y`, as `cells[ix][iy]`
/// (mean NaN for an empty cell). Rows with a non-finite value are left out.
pub fn binned_means_2d(
    x: &[f64],
    y: &[f64],
    z: &[f64],
    x_edges: &[f64],
    y_edges: &[f64],
) -> Vec<Vec<(usize, f64)>> {
    let (nx, ny) = (
        x_edges.len().saturating_sub(1),
        y_edges.len().saturating_sub(1),
    );
    let mut sums = vec![vec![(0usize, 0.0f64); ny]; nx];
    for ((&xi, &yi), &zi) in x.iter().zip(y).zip(z) {
        if !zi.is_finite() {
            continue;
        }
        if let (Some(i), Some(j)) = (bin_index(x_edges, xi), bin_index(y_edges, yi)) {
            sums[i][j].0 += 1;
            sums[i][j].1 += zi;
        }
    }
    sums.into_iter()
        .map(|col| {
            col.into_iter()
                .map(|(n, s)| (n, if n > 0 { s / n as f64 } else { f64::NAN }))
                .collect()
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bin_index_is_half_open_with_a_closed_last_bin() {
        let e = edges(0.0, 3.0, 3);
        assert_eq!(e, vec![0.0, 1.0, 2.0, 3.0]);
        assert_eq!(bin_index(&e, 0.0), Some(0));
        assert_eq!(bin_index(&e, 0.999), Some(0));
        assert_eq!(bin_index(&e, 1.0), Some(1));
        assert_eq!(bin_index(&e, 2.5), Some(2));
        assert_eq!(bin_index(&e, 3.0), Some(2));
        assert_eq!(bin_index(&e, -0.1), None);
        assert_eq!(bin_index(&e, 3.1), None);
        assert_eq!(bin_index(&e, f64::NAN), None);
    }

    #[test]
    fn binned_means_match_a_hand_computation() {
        // Bin [1, 2) holds x = 1.0, 1.5, 1.9 with y = 2, 4, 9; x = 2.0 falls in the next bin,
        // and the NaN residual is left out.
        let x = [0.5, 1.0, 1.5, 1.9, 2.0, 1.2, 7.0];
        let y = [10.0, 2.0, 4.0, 9.0, -1.0, f64::NAN, 3.0];
        let bins = binned_means(&x, &y, &edges(0.0, 3.0, 3));
        assert_eq!(bins.len(), 3);
        let b = bins[1];
        assert_eq!((b.lo, b.hi, b.count), (1.0, 2.0, 3));
        assert!((b.mean - 5.0).abs() < 1e-12);
        assert!((b.x_mean - 4.4 / 3.0).abs() < 1e-12);
        // Sample variance ((2-5)^2 + (4-5)^2 + (9-5)^2) / 2 = 13; s.e. = sqrt(13 / 3).
        assert!((b.std_err - (13.0f64 / 3.0).sqrt()).abs() < 1e-12);
        assert_eq!(bins[0].count, 1);
        assert_eq!(bins[0].mean, 10.0);
        assert!(bins[0].std_err.is_nan());
        assert_eq!((bins[2].count, bins[2].mean), (1, -1.0));
    }

    #[test]
    fn empty_bins_have_no_statistics() {
        let bins = binned_means(&[0.1], &[1.0], &edges(0.0, 2.0, 2));
        assert_eq!(bins[1].count, 0);
        assert!(bins[1].mean.is_nan());
    }

    #[test]
    fn grid_means_per_cell() {
        let x = [0.5, 0.5, 1.5, 1.5, 0.2];
        let y = [0.5, 0.6, 0.5, 1.5, 1.9];
        let z = [1.0, 3.0, -4.0, 8.0, 5.0];
        let e = edges(0.0, 2.0, 2);
        let g = binned_means_2d(&x, &y, &z, &e, &e);
        assert_eq!(g[0][0], (2, 2.0));
        assert_eq!(g[1][0], (1, -4.0));
        assert_eq!(g[1][1], (1, 8.0));
        assert_eq!(g[0][1], (1, 5.0));
    }
}
