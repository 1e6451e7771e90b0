//! One body for the serial and the parallel bake: [`Threads`] says how many
//! threads, [`map_in_order`] maps a slice in order on them. With the
//! `rayon` feature off, or with one thread, it is a plain loop; with it on,
//! rayon's `par_iter` over the same closure, collected in input order, so
//! the results (and so the bytes built from them) never depend on the
//! thread count.

use alloc::vec::Vec;

/// How many threads a bake may use.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Threads {
    /// Every core: rayon's global pool (its `RAYON_NUM_THREADS` or the
    /// number of logical CPUs). Without the `rayon` feature: one.
    All,
    /// Exactly this many (`1`, or `0`: serial, on the calling thread).
    /// Without the `rayon` feature: one.
    Exactly(usize),
}

impl Default for Threads {
    /// [`Threads::All`].
    fn default() -> Self {
        Threads::All
    }
}

/// Where [`map_in_order`] runs: the calling thread, or a rayon pool.
pub(crate) struct Runner {
    #[cfg(feature = "rayon")]
    pool: Option<Pool>,
}

#[cfg(feature = "rayon")]
enum Pool {
    /// The pool the caller runs in; outside any, rayon's global pool.
    Global,
    Own(rayon::ThreadPool),
}

impl Runner {
    /// A runner for `threads`. A pool rayon cannot start (the OS refused a
    /// thread) falls back to the calling thread: the output is the same.
    pub(crate) fn new(threads: Threads) -> Runner {
        #[cfg(feature = "rayon")]
        {
            let pool = match threads {
                Threads::All => Some(Pool::Global),
                Threads::Exactly(0 | 1) => None,
                // The pool the caller runs in (outside any: the global
                // one) when it has exactly `n` threads: its threads are
                // running already, and a new pool's would start cold on
                // every bake.
                Threads::Exactly(n) if n == rayon::current_num_threads() => Some(Pool::Global),
                Threads::Exactly(n) => rayon::ThreadPoolBuilder::new()
                    .num_threads(n)
                    .build()
                    .ok()
                    .map(Pool::Own),
            };
            Runner { pool }
        }
        #[cfg(not(feature = "rayon"))]
        {
            let _ = threads;
            Runner {}
        }
    }

    /// The runner on the calling thread alone.
    pub(crate) fn serial() -> Runner {
        Runner::new(Threads::Exactly(1))
    }

    /// The threads [`map_in_order`](Self::map_in_order) runs on.
    #[cfg_attr(not(feature = "rayon"), allow(clippy::unused_self))]
    pub(crate) fn threads(&self) -> usize {
        #[cfg(feature = "rayon")]
        match &self.pool {
            Some(Pool::Global) => return rayon::current_num_threads(),
            Some(Pool::Own(pool)) => return pool.current_num_threads(),
            None => {}
        }
        1
    }

    /// `items.iter().map(f).collect()`, on this runner's threads, results in
    /// the order of `items`. `min_len`: the fewest items one task takes
    /// (batches small work; ignored when serial).
    #[cfg_attr(not(feature = "rayon"), allow(clippy::unused_self))]
    pub(crate) fn map_in_order<T: Sync, R: Send>(
        &self,
        items: &[T],
        min_len: usize,
        f: impl Fn(&T) -> R + Sync + Send,
    ) -> Vec<R> {
        #[cfg(feature = "rayon")]
        {
            use rayon::prelude::*;
            let run = || {
                items
                    .par_iter()
                    .with_min_len(min_len.max(1))
                    .map(&f)
                    .collect()
            };
            match &self.pool {
                Some(Pool::Global) => return run(),
                Some(Pool::Own(pool)) => return pool.install(run),
                None => {}
            }
        }
        let _ = min_len;
        items.iter().map(f).collect()
    }
}

impl Runner {
    /// `f` on every item of `items` (each borrowed mutably by one call), on
    /// this runner's threads; in order when serial.
    #[cfg_attr(not(feature = "rayon"), allow(clippy::unused_self))]
    pub(crate) fn for_each_mut<T: Send>(&self, items: &mut [T], f: impl Fn(&mut T) + Sync + Send) {
        #[cfg(feature = "rayon")]
        {
            use rayon::prelude::*;
            match &self.pool {
                Some(Pool::Global) => return items.par_iter_mut().for_each(f),
                Some(Pool::Own(pool)) => {
                    return pool.install(|| items.par_iter_mut().for_each(f));
                }
                None => {}
            }
        }
        items.iter_mut().for_each(f);
    }
}

/// `f(k, &items[k])` for every `k`, results in order, on the thread pool
/// the caller runs in (rayon's global pool outside any), each thread
/// taking the lowest item no one has taken yet: the items in flight are
/// always the next few in order (where rayon's `par_iter` splits the slice
/// in halves, so that a thread may start far ahead). A speculative
/// walk that may be wasted past some item wants this. Without the `rayon`
/// feature, or on a pool of one thread, a plain loop.
pub(crate) fn map_claimed_in_order<T: Sync, R: Send>(
    items: &[T],
    f: impl Fn(usize, &T) -> R + Sync + Send,
) -> Vec<R> {
    #[cfg(feature = "rayon")]
    {
        use std::sync::atomic::{AtomicUsize, Ordering};
        use std::sync::Mutex;
        let threads = rayon::current_num_threads().min(items.len());
        if threads > 1 {
            let next = AtomicUsize::new(0);
            let slots: Vec<Mutex<Option<R>>> = items.iter().map(|_| Mutex::new(None)).collect();
            rayon::scope(|scope| {
                for _ in 0..threads {
                    scope.spawn(|_| loop {
                        let k = next.fetch_add(1, Ordering::Relaxed);
                        let Some(item) = items.get(k) else { break };
                        let result = f(k, item);
                        // A poisoned slot means `f` panicked on another
                        // thread: rayon propagates that panic anyway.
                        if let Ok(mut slot) = slots[k].lock() {
                            *slot = Some(result);
                        }
                    });
                }
            });
            return slots
                .into_iter()
                .map(|slot| {
                    slot.into_inner()
                        .ok()
                        .flatten()
                        .expect("every item was taken and finished")
                })
                .collect();
        }
    }
    items
        .iter()
        .enumerate()
        .map(|(k, item)| f(k, item))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_thread_count_keeps_the_order() {
        let items: Vec<u64> = (0..10_000).collect();
        let serial = Runner::new(Threads::Exactly(1)).map_in_order(&items, 1, |x| x * x);
        for threads in [Threads::All, Threads::Exactly(0), Threads::Exactly(3)] {
            for min_len in [1, 7, 5000] {
                let got = Runner::new(threads).map_in_order(&items, min_len, |x| x * x);
                assert_eq!(got, serial, "{threads:?} min_len {min_len}");
            }
        }
    }
}
