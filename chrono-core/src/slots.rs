//! The slot table behind generational handles: a handle `(index, generation)` names a slot,
//! the slot names a position in a dense array. Removal swap-removes from the dense array
//! (O(1)) and bumps the slot's generation, so every older handle of that slot is stale.

/// The accessors and `Display` (`"<label> <index>v<generation>"`) of a generational handle
/// type with private `index` and `generation` fields (bodies, items, joints, force
/// elements).
macro_rules! generational_handle {
    ($ty:ident, $label:literal) => {
        impl $ty {
            pub(crate) fn new(index: u32, generation: u32) -> Self {
                Self { index, generation }
            }

            /// The slot index (not the position in the system's dense array once
            /// entries were removed).
            pub fn index(self) -> u32 {
                self.index
            }

            /// The generation of the slot when the handle was issued.
            pub fn generation(self) -> u32 {
                self.generation
            }
        }

        impl std::fmt::Display for $ty {
            fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                write!(f, concat!($label, " {}v{}"), self.index, self.generation)
            }
        }
    };
}
pub(crate) use generational_handle;

/// One slot: its current generation and where its value sits in the dense array
/// (`None` while the slot is free).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Slot {
    generation: u32,
    dense: Option<u32>,
}

/// Handle -> dense index map with swap-remove (see the [module docs](self)).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub(crate) struct SlotTable {
    slots: Vec<Slot>,
    /// Slot of each dense position.
    owners: Vec<u32>,
    /// Free slots, reused last-freed first (deterministic).
    free: Vec<u32>,
}

/// What a removal did to the dense array: the value at `removed` left, and the last value
/// (`moved_from`, if it was not the removed one) now sits at `removed`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Removal {
    pub(crate) removed: usize,
    pub(crate) moved_from: Option<usize>,
}

impl SlotTable {
    /// A slot for a value pushed at the end of the dense array: `(index, generation)`.
    pub(crate) fn insert(&mut self) -> (u32, u32) {
        let dense = self.owners.len() as u32;
        let index = match self.free.pop() {
            Some(i) => {
                self.slots[i as usize].dense = Some(dense);
                i
            }
            None => {
                self.slots.push(Slot {
                    generation: 0,
                    dense: Some(dense),
                });
                self.slots.len() as u32 - 1
            }
        };
        self.owners.push(index);
        (index, self.slots[index as usize].generation)
    }

    /// The dense index of a live handle; `None` if it is stale or was never issued.
    #[inline]
    pub(crate) fn resolve(&self, index: u32, generation: u32) -> Option<usize> {
        let s = self.slots.get(index as usize)?;
        if s.generation != generation {
            return None;
        }
        s.dense.map(|d| d as usize)
    }

    /// The dense index of slot `index`, whatever its generation (callers hold live handles).
    #[inline]
    pub(crate) fn dense_unchecked(&self, index: u32) -> usize {
        self.slots[index as usize]
            .dense
            .map_or(usize::MAX, |d| d as usize)
    }

    /// `(index, generation)` of the value at dense position `dense`.
    pub(crate) fn handle_at(&self, dense: usize) -> (u32, u32) {
        let i = self.owners[dense];
        (i, self.slots[i as usize].generation)
    }

    /// Free the slot of a live handle; the caller swap-removes `removed` from its dense
    /// array. `None` if the handle is stale.
    pub(crate) fn remove(&mut self, index: u32, generation: u32) -> Option<Removal> {
        let removed = self.resolve(index, generation)?;
        let last = self.owners.len() - 1;
        self.owners.swap_remove(removed);
        let moved_from = (removed != last).then(|| {
            self.slots[self.owners[removed] as usize].dense = Some(removed as u32);
            last
        });
        let s = &mut self.slots[index as usize];
        s.dense = None;
        s.generation = s.generation.wrapping_add(1);
        self.free.push(index);
        Some(Removal {
            removed,
            moved_from,
        })
    }

    /// Slot -> dense index (`usize::MAX` for free slots), for per-step lookups by handle.
    pub(crate) fn dense_by_slot(&self) -> impl Iterator<Item = usize> + '_ {
        self.slots
            .iter()
            .map(|s| s.dense.map_or(usize::MAX, |d| d as usize))
    }
}
