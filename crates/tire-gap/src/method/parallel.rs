//! Work spread over the machine's cores, results in input order: rayon's work-stealing pool,
//! so that work started inside an item (the folds of one candidate's cross-validation) runs on
//! the cores the other items leave idle.

use std::cell::Cell;

use rayon::prelude::*;

thread_local! {
    /// The most threads the work of [`with_threads`] on this thread may use; `None`: every
    /// core (rayon's global pool).
    static THREADS: Cell<Option<usize>> = const { Cell::new(None) };
}

/// Runs `work` with [`parallel_map`] using at most `threads` threads (at least 1; 1 computes
/// on this thread alone). The results do not depend on it. A caller that runs several
/// diagnoses side by side (one per process of a Dask cluster) gives each its share of the
/// cores.
pub fn with_threads<R: Send>(threads: usize, work: impl FnOnce() -> R + Send) -> R {
    /// Puts the limit back when the work ends, also by unwinding.
    struct Restore(Option<usize>);
    impl Drop for Restore {
        fn drop(&mut self) {
            THREADS.with(|t| t.set(self.0));
        }
    }
    let threads = threads.max(1);
    let _restore = Restore(THREADS.with(|t| t.replace(Some(threads))));
    if threads == 1 {
        return work();
    }
    match rayon::ThreadPoolBuilder::new().num_threads(threads).build() {
        Ok(pool) => pool.install(work),
        // No threads to be had: the work on this thread alone.
        Err(_) => {
            THREADS.with(|t| t.set(Some(1)));
            work()
        }
    }
}

/// `f` over `items` on the cores of the current pool, results in input order. Items (and the
/// parallel work inside them) are taken by idle threads as they come, so the order in which
/// items are computed varies, but every result is `f` of its item alone. A panic in `f` goes
/// on in the caller with its own payload.
pub fn parallel_map<T: Sync, R: Send>(items: &[T], f: impl Fn(&T) -> R + Sync) -> Vec<R> {
    if items.len() <= 1 || THREADS.with(Cell::get) == Some(1) {
        return items.iter().map(f).collect();
    }
    items.par_iter().map(&f).collect()
}

/// `f` on each of `items`, each in place, on the cores of the current pool as
/// [`parallel_map`] spreads its items (e.g. pieces of one output, each filled by its own
/// computation).
pub fn parallel_for_each<T: Send>(items: &mut [T], f: impl Fn(&mut T) + Sync) {
    if items.len() <= 1 || THREADS.with(Cell::get) == Some(1) {
        items.iter_mut().for_each(f);
        return;
    }
    items.par_iter_mut().for_each(&f);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn results_come_in_input_order() {
        let items: Vec<u64> = (0..100).collect();
        // Uneven work, so threads finish out of order.
        let squares = parallel_map(&items, |&i| {
            std::thread::sleep(std::time::Duration::from_micros((100 - i) * 10));
            i * i
        });
        assert_eq!(squares, items.iter().map(|i| i * i).collect::<Vec<_>>());
        assert!(parallel_map(&[] as &[u64], |&i| i).is_empty());
        // In place, each item its own.
        let mut pieces: Vec<(u64, u64)> = items.iter().map(|&i| (i, 0)).collect();
        parallel_for_each(&mut pieces, |(i, square)| *square = *i * *i);
        assert!(pieces.iter().all(|(i, square)| *square == i * i));
        // Work inside an item spread too, each level in its own order.
        let nested = parallel_map(&items[..10], |&i| parallel_map(&items[..5], |&j| i * j));
        for (i, row) in nested.iter().enumerate() {
            assert_eq!(*row, (0..5).map(|j| i as u64 * j).collect::<Vec<_>>());
        }
    }

    #[test]
    fn one_thread_computes_on_the_callers_thread_with_the_same_results() {
        let items: Vec<u64> = (0..50).collect();
        let caller = std::thread::current().id();
        let (alone, threads): (Vec<u64>, Vec<_>) = with_threads(1, || {
            parallel_map(&items, |&i| (i * i, std::thread::current().id()))
        })
        .into_iter()
        .unzip();
        assert!(threads.iter().all(|t| *t == caller));
        assert_eq!(alone, parallel_map(&items, |&i| i * i));
        // The limit ends with the call: the work goes to the pool's threads again.
        let ids = parallel_map(&items, |_| std::thread::current().id());
        assert!(ids.iter().any(|t| *t != caller));
        // A limit above one: the same results from a pool of that size.
        let pooled = with_threads(2, || parallel_map(&items, |&i| i * i));
        assert_eq!(pooled, alone);
    }
}
