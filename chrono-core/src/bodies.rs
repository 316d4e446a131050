//! [`Bodies`]: the rigid bodies of a system, dense in memory, named by generational
//! [`BodyHandle`]s.
//!
//! The bodies sit in one `Vec` (a slice for the solver and collision loops); a slot table
//! maps each handle's index to its position. Removing a body swap-removes it (the last body
//! takes its place, its handle stays valid) and bumps the slot's generation, so an older
//! handle of that slot is stale: looking it up is `None` (or an error naming it from
//! [`System`](crate::System)), never another body.

use std::ops::{Deref, DerefMut, Index, IndexMut};

use crate::body::{BodyHandle, RigidBody};
use crate::error::{ChronoError, Result};
use crate::slots::{Removal, SlotTable};

/// The rigid bodies, dense, with their handles (see the [module docs](self)). Derefs to the
/// slice of bodies in dense order; `bodies[i]` is the body at dense position `i`, `bodies[h]` looks up a live handle (and panics on a stale
/// one: use [`get`](Self::get) for handles that may be stale).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Bodies {
    dense: Vec<RigidBody>,
    table: SlotTable,
}

impl Bodies {
    /// No bodies.
    pub fn new() -> Self {
        Self::default()
    }

    /// These bodies, with handles issued in order (for items and force elements used outside
    /// a [`System`](crate::System), e.g. in tests).
    pub fn from_bodies(bodies: Vec<RigidBody>) -> Self {
        let mut set = Self::new();
        for b in bodies {
            set.insert(b);
        }
        set
    }

    /// Add a body at the end; its new handle.
    pub fn insert(&mut self, body: RigidBody) -> BodyHandle {
        let (index, generation) = self.table.insert();
        self.dense.push(body);
        BodyHandle::new(index, generation)
    }

    /// Remove a body (swap-remove: the last body moves into its place). A stale handle is
    /// [`ChronoError::StaleBody`].
    pub(crate) fn remove(&mut self, h: BodyHandle) -> Result<(RigidBody, Removal)> {
        let r = (self.table)
            .remove(h.index(), h.generation())
            .ok_or(ChronoError::StaleBody { handle: h })?;
        Ok((self.dense.swap_remove(r.removed), r))
    }

    /// The dense index of `h` (its position in the slice), `None` if stale.
    #[inline]
    pub fn dense_index(&self, h: BodyHandle) -> Option<usize> {
        self.table.resolve(h.index(), h.generation())
    }

    /// The dense index of `h`, or [`ChronoError::StaleBody`] naming it.
    pub fn try_index(&self, h: BodyHandle) -> Result<usize> {
        self.dense_index(h)
            .ok_or(ChronoError::StaleBody { handle: h })
    }

    /// Whether `h` names a body here.
    pub fn contains(&self, h: BodyHandle) -> bool {
        self.dense_index(h).is_some()
    }

    /// The body `h`, `None` if stale.
    #[inline]
    pub fn get(&self, h: BodyHandle) -> Option<&RigidBody> {
        self.dense_index(h).map(|i| &self.dense[i])
    }

    /// The body `h`, mutable, `None` if stale.
    #[inline]
    pub fn get_mut(&mut self, h: BodyHandle) -> Option<&mut RigidBody> {
        self.dense_index(h).map(|i| &mut self.dense[i])
    }

    /// The handle of the body at dense position `i` (panics past the end).
    pub fn handle(&self, i: usize) -> BodyHandle {
        let (index, generation) = self.table.handle_at(i);
        BodyHandle::new(index, generation)
    }

    /// The handles of all bodies, in dense order.
    pub fn handles(&self) -> impl ExactSizeIterator<Item = BodyHandle> + '_ {
        (0..self.dense.len()).map(|i| self.handle(i))
    }

    /// `(handle, body)` of all bodies, in dense order.
    pub fn iter_with_handles(&self) -> impl ExactSizeIterator<Item = (BodyHandle, &RigidBody)> {
        self.dense
            .iter()
            .enumerate()
            .map(|(i, b)| (self.handle(i), b))
    }

    /// The bodies in dense order.
    pub fn as_slice(&self) -> &[RigidBody] {
        &self.dense
    }

    /// Slot -> dense index (`usize::MAX` for free slots), for [`BodyLoads`](crate::force::BodyLoads).
    pub(crate) fn dense_by_slot(&self) -> impl Iterator<Item = usize> + '_ {
        self.table.dense_by_slot()
    }
}

impl Deref for Bodies {
    type Target = [RigidBody];
    fn deref(&self) -> &[RigidBody] {
        &self.dense
    }
}

impl DerefMut for Bodies {
    fn deref_mut(&mut self) -> &mut [RigidBody] {
        &mut self.dense
    }
}

impl Index<BodyHandle> for Bodies {
    type Output = RigidBody;
    #[inline]
    fn index(&self, h: BodyHandle) -> &RigidBody {
        &self.dense[self.table.dense_unchecked(h.index())]
    }
}

impl IndexMut<BodyHandle> for Bodies {
    #[inline]
    fn index_mut(&mut self, h: BodyHandle) -> &mut RigidBody {
        &mut self.dense[self.table.dense_unchecked(h.index())]
    }
}

impl Index<usize> for Bodies {
    type Output = RigidBody;
    #[inline]
    fn index(&self, i: usize) -> &RigidBody {
        &self.dense[i]
    }
}

impl IndexMut<usize> for Bodies {
    #[inline]
    fn index_mut(&mut self, i: usize) -> &mut RigidBody {
        &mut self.dense[i]
    }
}

impl<'a> IntoIterator for &'a Bodies {
    type Item = &'a RigidBody;
    type IntoIter = std::slice::Iter<'a, RigidBody>;
    fn into_iter(self) -> Self::IntoIter {
        self.dense.iter()
    }
}

impl<'a> IntoIterator for &'a mut Bodies {
    type Item = &'a mut RigidBody;
    type IntoIter = std::slice::IterMut<'a, RigidBody>;
    fn into_iter(self) -> Self::IntoIter {
        self.dense.iter_mut()
    }
}
