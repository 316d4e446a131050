//! Removing bodies, joints, force elements and physics items from a [`System`] (see its
//! "Handles and removal" docs).

use std::collections::HashSet;

use crate::body::{BodyHandle, RigidBody};
use crate::error::{ChronoError, Result};
use crate::force::{ForceElement, ForceHandle};
use crate::item::{ItemHandle, PhysicsItem};
use crate::joint::{Joint, JointHandle};

use super::System;

impl System {
    /// Remove a body and its colliders; the body is returned. The last body of
    /// [`bodies`](Self::bodies) moves into its place (its handle stays valid); `h` and any
    /// copy of it are stale from now on ([`ChronoError::StaleBody`] on use, as is removing
    /// a stale handle). One removal of [`remove_bodies`](Self::remove_bodies), which says
    /// what it costs and keeps.
    ///
    /// A body that a joint or force element refers to is not removed:
    /// [`ChronoError::BodyInUse`] names them (remove them first,
    /// [`remove_joint`](Self::remove_joint), [`remove_force_element`](Self::remove_force_element)).
    /// Physics items that attached the body must be removed (or detach it) first: the
    /// system cannot see their references.
    pub fn remove_body(&mut self, h: BodyHandle) -> Result<RigidBody> {
        let mut removed = self.remove_bodies(&[h])?;
        Ok(removed.pop().expect("one body per handle"))
    }

    /// Remove several bodies at once, in the order given (each a swap-remove as
    /// [`remove_body`](Self::remove_body)); the bodies are returned in that order.
    ///
    /// All handles are checked first: a stale handle ([`ChronoError::StaleBody`]), a
    /// handle given twice ([`ChronoError::InvalidParameter`] naming `handles[k]`) or a body
    /// still used by a joint or force element ([`ChronoError::BodyInUse`]) is an error
    /// that leaves the system unchanged.
    ///
    /// Cost: O(1) per body for the bodies; the collision world is updated in place, O(k)
    /// per body for its k colliders plus, once per call, one pass over the colliders and
    /// the pair states ([`CollisionWorld::remove_owners`](crate::collision::CollisionWorld::remove_owners));
    /// the warm-start and SMC history caches are remapped once per call (O(cached
    /// contacts)). So many removals in one call cost about one. Contacts of the removed
    /// bodies are dropped from these caches; the other contacts keep their warm start,
    /// their history and their narrow-phase state (except a pair whose collider ids swap
    /// order, which restarts cold). The contacts reported by [`contacts`](Self::contacts)
    /// are cleared until the next step.
    pub fn remove_bodies(&mut self, handles: &[BodyHandle]) -> Result<Vec<RigidBody>> {
        let mut seen = HashSet::with_capacity(handles.len());
        for (k, &h) in handles.iter().enumerate() {
            self.bodies.try_index(h)?;
            if !seen.insert(h) {
                return Err(ChronoError::invalid(
                    format!("handles[{k}]"),
                    h,
                    "is given twice",
                ));
            }
        }
        self.check_not_in_use(handles, &seen)?;
        if handles.is_empty() {
            return Ok(Vec::new());
        }
        let mut bodies = Vec::with_capacity(handles.len());
        let mut removals = Vec::with_capacity(handles.len());
        for &h in handles {
            let (body, r) = self.bodies.remove(h)?;
            removals.push((r.removed as u32, r.moved_from.map(|m| m as u32)));
            if r.removed < self.contact_friction.len() {
                let last = self.bodies.len();
                self.contact_friction.resize(last + 1, None);
                self.contact_friction.swap_remove(r.removed);
            }
            bodies.push(body);
        }
        let map = self.collision.remove_owners(&removals);
        self.cache.remap(Some(&map), &Some);
        self.smc.remap_colliders(&map);
        // The last step's per-body buffers name old indices.
        self.contacts.clear();
        self.points.clear();
        self.proxy_contacts.clear();
        self.proxy_points.clear();
        self.loads.reset(&self.bodies);
        self.loads_zero = false;
        self.poses_fresh = false;
        Ok(bodies)
    }

    /// [`ChronoError::BodyInUse`] for the first of `handles` a joint or force element
    /// refers to (`set` holds the same handles).
    fn check_not_in_use(&self, handles: &[BodyHandle], set: &HashSet<BodyHandle>) -> Result<()> {
        let joint_users = self
            .joint_handles()
            .zip(&self.joints)
            .filter_map(|(jh, j)| {
                let (a, b) = j.bodies();
                (set.contains(&a) || set.contains(&b))
                    .then(|| ([a, b], format!("{jh} (\"{}\")", j.name())))
            });
        let mut users: Vec<(Vec<BodyHandle>, String)> =
            joint_users.map(|(b, s)| (b.to_vec(), s)).collect();
        users.extend(
            (self.force_handles().zip(&self.force_elements))
                .map(|(fh, e)| (e.body_handles(), fh, e))
                .filter(|(bs, ..)| bs.iter().any(|b| set.contains(b)))
                .map(|(bs, fh, e)| (bs, format!("{fh} (\"{}\")", e.name()))),
        );
        if users.is_empty() {
            return Ok(());
        }
        let h = *handles
            .iter()
            .find(|h| users.iter().any(|(bs, _)| bs.contains(h)))
            .expect("a user names one of the handles");
        Err(ChronoError::BodyInUse {
            handle: h,
            name: self.body(h)?.name().to_string(),
            users: (users.into_iter())
                .filter(|(bs, _)| bs.contains(&h))
                .map(|(_, s)| s)
                .collect(),
        })
    }

    /// Remove a joint; it is returned. The last joint moves into its place (its handle
    /// stays valid); `h` is stale from now on ([`ChronoError::StaleJoint`] on use). Contacts
    /// between its two bodies, disabled by [`add_joint`](Self::add_joint), are enabled
    /// again unless another joint still joins them. O(joints) (the check for another joint).
    pub fn remove_joint(&mut self, h: JointHandle) -> Result<Joint> {
        let r = (self.joint_slots)
            .remove(h.index(), h.generation())
            .ok_or(ChronoError::StaleJoint { handle: h })?;
        let joint = self.joints.swap_remove(r.removed);
        let pair = |j: &Joint| {
            let (a, b) = j.bodies();
            (a.min(b), a.max(b))
        };
        let key = pair(&joint);
        // Both bodies are live: a jointed body cannot be removed.
        let dense = (
            self.bodies.dense_index(key.0),
            self.bodies.dense_index(key.1),
        );
        if let (Some(a), Some(b)) = dense
            && !self.joints.iter().any(|j| pair(j) == key)
        {
            self.collision.include_pair(a as u32, b as u32);
        }
        Ok(joint)
    }

    /// Remove a force element; it is returned. The last element moves into its place (its
    /// handle stays valid); `h` is stale from now on ([`ChronoError::StaleForce`] on use).
    /// O(1). The loads of the last step ([`element_loads`](Self::element_loads)) keep its
    /// contribution until the next step.
    pub fn remove_force_element(&mut self, h: ForceHandle) -> Result<Box<dyn ForceElement>> {
        let r = (self.force_slots)
            .remove(h.index(), h.generation())
            .ok_or(ChronoError::StaleForce { handle: h })?;
        Ok(self.force_elements.swap_remove(r.removed))
    }

    /// Remove a physics item; it is returned. The last item moves into its place (its
    /// handle stays valid); `h` is stale from now on ([`ChronoError::StaleItem`] on use).
    /// O(1) plus the warm-start cache of proxy contacts (entries of the item dropped).
    pub fn remove_item(&mut self, h: ItemHandle) -> Result<Box<dyn PhysicsItem>> {
        let r = (self.item_slots)
            .remove(h.index(), h.generation())
            .ok_or(ChronoError::StaleItem { handle: h })?;
        let item = self.items.swap_remove(r.removed);
        let (removed, moved) = (r.removed as u32, r.moved_from.map(|m| m as u32));
        self.cache.remap(None, &|i| {
            if i == removed {
                None
            } else if Some(i) == moved {
                Some(removed)
            } else {
                Some(i)
            }
        });
        self.proxy_contacts.clear();
        self.proxy_points.clear();
        self.proxies.clear();
        Ok(item)
    }
}
