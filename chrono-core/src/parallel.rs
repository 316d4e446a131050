//! Where a step's parallel loops start from.
//!
//! A `par_iter` called from a thread outside rayon's pool (a program's main thread)
//! hands its work to the pool and blocks until a worker has finished it: every parallel
//! loop of a step then pays a cross-thread hand-off and wake-up, and a step has dozens of
//! short loops. On 2 cores this made the small granular and vehicle scenes 15-40 %
//! *slower* on two threads than on one (137 000 voluntary context switches in the
//! 13 s `granular-shear --quick`, 0.5-2.5 s of system time; docs/performance.md
//! "Steps on a worker"). Running the whole step on one worker thread makes the hand-off
//! once per step and lets the loops inside split and join on the pool's own threads.
//! Results do not change: where a closure runs does not change what it computes.

/// Run `f` on a rayon worker thread: inline when the caller already is one (of any pool,
/// e.g. inside `ThreadPool::install`), otherwise by handing it once to the global pool
/// (`rayon::scope` runs its closure on a worker), whose threads then run `f`'s parallel
/// loops as they would have anyway.
pub fn on_worker<R: Send>(f: impl FnOnce() -> R + Send) -> R {
    if rayon::current_thread_index().is_some() {
        f()
    } else {
        rayon::scope(|_| f())
    }
}

#[cfg(test)]
mod tests {
    use super::on_worker;

    #[test]
    fn the_closure_runs_on_a_pool_thread_and_returns_its_value() {
        assert!(rayon::current_thread_index().is_none());
        let (idx, v) = on_worker(|| (rayon::current_thread_index(), 41 + 1));
        assert!(idx.is_some(), "the closure ran outside the pool");
        assert_eq!(v, 42);
        // Nested: stays on the same worker.
        let (a, b) = on_worker(|| {
            let a = rayon::current_thread_index();
            (a, on_worker(rayon::current_thread_index))
        });
        assert_eq!(a, b);
    }
}
