//! Removing owners from a [`CollisionWorld`] in place (what a swap-remove of bodies does to
//! the colliders), keeping the broad and narrow phase's state of the other colliders.
//!
//! Invariant: the colliders are sorted by owner (grouped, owners ascending; within an
//! owner, in the order they were added), as a world built by adding the owners in order
//! has them. A swap-remove of owner `o` (the last owner `m` takes its number) then moves
//! `m`'s block of colliders into `o`'s place: the other colliders keep their relative order,
//! so the sorted lists keyed by collider id (pair states, candidates) only need the few
//! entries of `m` put back in place, and the world looks exactly as if it had been built
//! without `o`, in the new owner order.

use super::narrow_phase::PairKind;
use super::world::{ColliderKind, CollisionWorld};

/// One swap-remove on a vector laid out like the colliders: the block
/// `[start, start + removed)` leaves, the block `[moved_at, moved_at + moved)` takes its
/// place, the colliders between them shift by `moved - removed`, those after by `-removed`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Splice {
    start: usize,
    removed: usize,
    moved_at: usize,
    moved: usize,
}

impl Splice {
    /// Apply to `v` (the colliders or a vector parallel to them). O(k) when the two blocks
    /// have the same length (a swap, then a truncation when nothing follows the moved
    /// block), else one `memmove` of the entries between the blocks.
    fn apply<T>(&self, v: &mut Vec<T>) {
        let Splice {
            start: s,
            removed: ko,
            moved_at: t,
            moved: kl,
        } = *self;
        if ko == kl {
            for i in 0..kl {
                v.swap(s + i, t + i);
            }
            v.drain(t..t + kl);
        } else {
            let moved: Vec<T> = v.drain(t..t + kl).collect();
            v.splice(s..s + ko, moved);
        }
    }
}

impl CollisionWorld {
    /// Drop the colliders of `owner` and renumber the owner `moved_from` (if any) to
    /// `owner`: what a swap-remove of owner `owner` from the owner arrays does. See
    /// [`remove_owners`](Self::remove_owners) (this is one removal of it).
    pub fn remove_owner(&mut self, owner: u32, moved_from: Option<u32>) -> Vec<Option<u32>> {
        self.remove_owners(&[(owner, moved_from)])
    }

    /// Apply a sequence of swap-removes `(owner, moved_from)` of owners, in order (each as
    /// [`remove_owner`](Self::remove_owner): the colliders of `owner` are dropped, those of
    /// `moved_from` (the last owner, if it was not `owner`) are renumbered to `owner`).
    /// Returns the new id of each collider of before the call (`None` for the dropped
    /// ones), for the caches keyed by collider.
    ///
    /// The colliders stay sorted by owner, so the world is the one built without the
    /// removed owners, in the new order. The state of the other colliders is kept: excluded
    /// owner pairs are renumbered, the narrow phase's pair states (parry's manifolds) follow
    /// their colliders' new ids (a pair whose two ids swap order starts afresh, as the
    /// warm-start cache does with its contacts), the sort-and-sweep keeps its order (only a
    /// hint for its sort).
    ///
    /// Cost, per removal: O(log n) to find the two blocks, O(k) to move them (k the
    /// colliders of the two owners) when both owners have as many colliders, else a
    /// `memmove` of the colliders between them; O(excluded pairs). Per call: one O(n) pass
    /// to build the map and one pass over the pair states (which are re-sorted only if a
    /// moved collider's pairs are out of order: a nearly sorted stable sort); the sphere
    /// grid re-indexes its sphere list in the next [`detect`](Self::detect) (one pass over
    /// the colliders, as the bounds are anyway). No sort of the colliders, unless colliders
    /// were added out of owner order (then they are sorted once, stably, by owner).
    pub fn remove_owners(&mut self, removals: &[(u32, Option<u32>)]) -> Vec<Option<u32>> {
        let n = self.colliders.len();
        // Current position -> id before the call.
        let mut orig: Vec<u32> = (0..n as u32).collect();
        if !self.owner_sorted {
            self.sort_by_owner(&mut orig);
        }
        for &(owner, moved_from) in removals {
            self.remove_one(owner, moved_from, &mut orig);
        }
        let mut map = vec![None; n];
        for (new, &old) in orig.iter().enumerate() {
            map[old as usize] = Some(new as u32);
        }
        self.remap_pairs(&map);
        self.grid.forget_index();
        self.owner_bound = None;
        self.hot_stale = true;
        map
    }

    /// Stable sort of the colliders (and the vectors parallel to them) by owner.
    fn sort_by_owner(&mut self, orig: &mut Vec<u32>) {
        let n = self.colliders.len();
        let mut order: Vec<usize> = (0..n).collect();
        order.sort_by_key(|&i| self.colliders[i].owner);
        let mut old: Vec<Option<_>> = self.colliders.drain(..).map(Some).collect();
        self.colliders
            .extend(order.iter().map(|&i| old[i].take().expect("a permutation")));
        *orig = order.iter().map(|&i| orig[i]).collect();
        if self.poses.len() == n && self.bounds.len() == n {
            self.poses = order.iter().map(|&i| self.poses[i]).collect();
            self.bounds = order.iter().map(|&i| self.bounds[i]).collect();
        } else {
            self.poses.clear();
            self.bounds.clear();
        }
        self.owner_sorted = true;
    }

    /// One swap-remove (colliders sorted by owner).
    fn remove_one(&mut self, owner: u32, moved_from: Option<u32>, orig: &mut Vec<u32>) {
        let block = |o: u32| {
            let lo = self.colliders.partition_point(|c| c.owner < o);
            let hi = self.colliders.partition_point(|c| c.owner <= o);
            (lo, hi)
        };
        let (s, e) = block(owner);
        let moved_from = moved_from.filter(|&m| m != owner);
        let splice = match moved_from {
            Some(m) if m > owner => {
                let (t, te) = block(m);
                Splice {
                    start: s,
                    removed: e - s,
                    moved_at: t,
                    moved: te - t,
                }
            }
            // Not a swap-remove from the end (the moved owner is below the removed one):
            // drop, renumber, and sort.
            Some(m) => {
                self.drop_block(s, e, orig);
                for c in &mut self.colliders[..s] {
                    if c.owner == m {
                        c.owner = owner;
                    }
                }
                self.owner_sorted = false;
                self.sort_by_owner(orig);
                self.renumber_excluded(owner, Some(m));
                return;
            }
            None => Splice {
                start: s,
                removed: e - s,
                moved_at: e,
                moved: 0,
            },
        };
        self.spheres -= (self.colliders[s..e].iter())
            .filter(|c| matches!(c.kind, ColliderKind::Sphere { .. }))
            .count();
        let n = self.colliders.len();
        splice.apply(&mut self.colliders);
        splice.apply(orig);
        if self.poses.len() == n && self.bounds.len() == n {
            splice.apply(&mut self.poses);
            splice.apply(&mut self.bounds);
        } else {
            self.poses.clear();
            self.bounds.clear();
        }
        for c in &mut self.colliders[s..s + splice.moved] {
            c.owner = owner;
        }
        self.renumber_excluded(owner, moved_from);
    }

    /// Drop the colliders `[s, e)` (and their entries in the parallel vectors).
    fn drop_block(&mut self, s: usize, e: usize, orig: &mut Vec<u32>) {
        self.spheres -= (self.colliders[s..e].iter())
            .filter(|c| matches!(c.kind, ColliderKind::Sphere { .. }))
            .count();
        let n = self.colliders.len();
        self.colliders.drain(s..e);
        orig.drain(s..e);
        if self.poses.len() == n && self.bounds.len() == n {
            self.poses.drain(s..e);
            self.bounds.drain(s..e);
        } else {
            self.poses.clear();
            self.bounds.clear();
        }
    }

    /// Excluded pairs after the swap-remove of `owner`: its pairs dropped, those of
    /// `moved_from` renumbered to `owner` and put back in order.
    fn renumber_excluded(&mut self, owner: u32, moved_from: Option<u32>) {
        let mut renumbered = Vec::new();
        self.excluded.retain(|&(a, b)| {
            if a == owner || b == owner {
                return false;
            }
            if moved_from.is_some_and(|m| a == m || b == m) {
                let r = |o: u32| if Some(o) == moved_from { owner } else { o };
                let (a, b) = (r(a), r(b));
                renumbered.push((a.min(b), a.max(b)));
                return false;
            }
            true
        });
        for key in renumbered {
            if let Err(at) = self.excluded.binary_search(&key) {
                self.excluded.insert(at, key);
            }
        }
    }

    /// The pair states after the colliders were renumbered by `map`: those of a dropped
    /// collider go to the spare buffers, the others follow their ids; kept sorted.
    fn remap_pairs(&mut self, map: &[Option<u32>]) {
        let mut kept = std::mem::take(&mut self.next_pairs);
        kept.clear();
        for mut p in self.pairs.drain(..) {
            match (map[p.a as usize], map[p.b as usize]) {
                (Some(a), Some(b)) if a < b => {
                    p.a = a;
                    p.b = b;
                    kept.push(p);
                }
                (Some(a), Some(b)) => {
                    // The manifolds are oriented from a to b: start the pair afresh.
                    let kind =
                        PairKind::of(&self.colliders[b as usize], &self.colliders[a as usize]);
                    p.reset(b, a, kind);
                    kept.push(p);
                }
                _ => self.spare.push(p),
            }
        }
        if !kept.is_sorted_by_key(|p| (p.a, p.b)) {
            kept.sort_by_key(|p| (p.a, p.b));
        }
        self.next_pairs = std::mem::replace(&mut self.pairs, kept);
    }
}
