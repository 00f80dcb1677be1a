//! Work spread over the machine's cores, results in input order.

use std::cell::Cell;
use std::sync::atomic::{AtomicUsize, Ordering};

thread_local! {
    /// The most threads `parallel_map` uses when called on this thread; `None`: every core.
    static THREADS: Cell<Option<usize>> = const { Cell::new(None) };
}

/// Runs `work` with [`parallel_map`] on this thread using at most `threads` threads (at
/// least 1; 1 computes on this thread alone). The results do not depend on it. A caller that
/// runs several diagnoses side by side (one per process of a Dask cluster) gives each its
/// share of the cores.
pub fn with_threads<R>(threads: usize, work: impl FnOnce() -> R) -> R {
    /// Puts the limit back when the work ends, also by unwinding.
    struct Restore(Option<usize>);
    impl Drop for Restore {
        fn drop(&mut self) {
            THREADS.with(|t| t.set(self.0));
        }
    }
    let _restore = Restore(THREADS.with(|t| t.replace(Some(threads.max(1)))));
    work()
}

/// `f` over `items` on all available cores, results in input order. Each thread takes the
/// next item not yet taken, so the order in which items are computed varies, but every
/// result is `f` of its item alone. A panic in `f` goes on in the caller with its own payload.
pub fn parallel_map<T: Sync, R: Send>(items: &[T], f: impl Fn(&T) -> R + Sync) -> Vec<R> {
    let threads = THREADS
        .with(Cell::get)
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()))
        .min(items.len().max(1));
    if threads == 1 {
        return items.iter().map(f).collect();
    }
    let next = AtomicUsize::new(0);
    let mut results: Vec<(usize, R)> = std::thread::scope(|scope| {
        let workers: Vec<_> = (0..threads)
            .map(|_| {
                scope.spawn(|| {
                    let mut done = Vec::new();
                    loop {
                        let i = next.fetch_add(1, Ordering::Relaxed);
                        let Some(item) = items.get(i) else { break };
                        done.push((i, f(item)));
                    }
                    done
                })
            })
            .collect();
        workers
            .into_iter()
            .flat_map(|w| w.join().unwrap_or_else(|p| std::panic::resume_unwind(p)))
            .collect()
    });
    results.sort_by_key(|(i, _)| *i);
    results.into_iter().map(|(_, r)| r).collect()
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
        // The limit ends with the call.
        let ids = parallel_map(&items, |_| std::thread::current().id());
        let spread = ids.iter().any(|t| *t != caller);
        let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
        assert_eq!(spread, cores > 1);
    }
}
