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

/// Extend `v` to length `n` with copies of `x`, in parallel (rayon writes the new slots
/// in place): the serial fill of a large buffer is a step's critical path on two threads.
pub(crate) fn grow<T: Clone + Send + Sync>(v: &mut Vec<T>, n: usize, x: T) {
    use rayon::prelude::*;
    let add = n.saturating_sub(v.len());
    v.par_extend(rayon::iter::repeat_n(x, add));
}

/// Split `s` into consecutive parts of the given lengths (for tasks that each fill their
/// own part).
pub(crate) fn split_parts<T>(mut s: &mut [T], lens: impl Iterator<Item = usize>) -> Vec<&mut [T]> {
    let mut parts = Vec::new();
    for n in lens {
        let (a, rest) = s.split_at_mut(n);
        parts.push(a);
        s = rest;
    }
    parts
}

/// Append the concatenation of `parts` to `out`, the copies in parallel (each part into
/// its own slice of `out`): the same values, in the same order, as extending part by part.
pub(crate) fn append_parts<T: Copy + Send + Sync>(out: &mut Vec<T>, parts: &[Vec<T>]) {
    use rayon::prelude::*;
    let total: usize = parts.iter().map(Vec::len).sum();
    let Some(&first) = parts.iter().find_map(|p| p.first()) else {
        return;
    };
    let start = out.len();
    grow(out, start + total, first);
    split_parts(&mut out[start..], parts.iter().map(Vec::len))
        .into_par_iter()
        .zip(parts.par_iter())
        .for_each(|(o, p)| o.copy_from_slice(p));
}

#[cfg(test)]
mod tests {
    use super::{append_parts, on_worker};

    #[test]
    fn appended_parts_are_the_concatenation() {
        let parts: Vec<Vec<u32>> = (0..37).map(|k| (0..(k * 7) % 11).collect()).collect();
        let mut out = vec![99, 98];
        append_parts(&mut out, &parts);
        let mut want = vec![99, 98];
        for p in &parts {
            want.extend_from_slice(p);
        }
        assert_eq!(out, want);
        append_parts(&mut out, &[Vec::new(), Vec::new()]);
        assert_eq!(out, want);
    }

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
