//! Cross-validation grouped by run: a whole test block is either fitted or scored, never split.

use std::collections::BTreeMap;

/// An assignment of runs to `k` folds.
#[derive(Debug, Clone)]
pub struct Folds {
    pub k: usize,
    /// The split seed (reported for provenance).
    pub seed: u64,
    fold_of: BTreeMap<i64, usize>,
}

/// A small deterministic generator (splitmix64), so the split is the same on every platform.
pub(crate) fn splitmix(state: &mut u64) -> u64 {
    *state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
    let mut z = *state;
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

impl Folds {
    /// Shuffles the runs with `seed`, then deals them to the fold with the fewest rows so far,
    /// largest runs first, so folds hold similar amounts of data.
    pub fn new(runs: &[i64], k: usize, seed: u64) -> Folds {
        let mut sizes: BTreeMap<i64, usize> = BTreeMap::new();
        for r in runs {
            *sizes.entry(*r).or_default() += 1;
        }
        let mut state = seed;
        let mut order: Vec<(i64, usize, u64)> = sizes
            .into_iter()
            .map(|(r, n)| (r, n, splitmix(&mut state)))
            .collect();
        order.sort_by_key(|&(_, n, tie)| (std::cmp::Reverse(n), tie));
        let k = k.max(1);
        let mut load = vec![0usize; k];
        let mut fold_of = BTreeMap::new();
        for (run, n, _) in order {
            let fold = (0..k).min_by_key(|&f| (load[f], f)).unwrap_or(0);
            load[fold] += n;
            fold_of.insert(run, fold);
        }
        Folds { k, seed, fold_of }
    }

    /// Number of distinct runs.
    pub fn runs(&self) -> usize {
        self.fold_of.len()
    }

    pub fn fold_of(&self, run: i64) -> usize {
        self.fold_of.get(&run).copied().unwrap_or(0)
    }

    /// Positions of `run_of_row` in the training folds and in fold `fold`.
    pub fn split(&self, run_of_row: &[i64], fold: usize) -> (Vec<usize>, Vec<usize>) {
        let (mut train, mut test) = (Vec::new(), Vec::new());
        // A run's rows mostly follow each other: look its fold up once per stretch.
        let mut last: Option<(i64, usize)> = None;
        for (i, &run) in run_of_row.iter().enumerate() {
            let f = match last {
                Some((r, f)) if r == run => f,
                _ => self.fold_of(run),
            };
            last = Some((run, f));
            if f == fold { &mut test } else { &mut train }.push(i);
        }
        (train, test)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn runs_are_never_split_and_folds_are_balanced() {
        let runs: Vec<i64> = (0..30)
            .flat_map(|r| std::iter::repeat_n(r, 50 + (r as usize % 7) * 10))
            .collect();
        let folds = Folds::new(&runs, 5, 42);
        assert_eq!(folds.runs(), 30);
        let mut sizes = Vec::new();
        for fold in 0..5 {
            let (train, test) = folds.split(&runs, fold);
            assert_eq!(train.len() + test.len(), runs.len());
            sizes.push(test.len());
            for &i in &test {
                assert!(
                    train.iter().all(|&j| runs[j] != runs[i]),
                    "run {} split",
                    runs[i]
                );
            }
        }
        let (lo, hi) = (sizes.iter().min().unwrap(), sizes.iter().max().unwrap());
        assert!(hi - lo <= 110, "{sizes:?}");
        // Same seed, same split; another seed, another split.
        assert_eq!(Folds::new(&runs, 5, 42).fold_of, folds.fold_of);
        assert_ne!(Folds::new(&runs, 5, 43).fold_of, folds.fold_of);
    }
}
