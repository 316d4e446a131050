//! Removing bodies and physics items from a [`System`] (see its "Handles and removal" docs).

use crate::body::{BodyHandle, RigidBody};
use crate::error::{ChronoError, Result};
use crate::item::{ItemHandle, PhysicsItem};

use super::System;

impl System {
    /// Remove a body and its colliders; the body is returned. The last body of
    /// [`bodies`](Self::bodies) moves into its place (its handle stays valid); `h` and any
    /// copy of it are stale from now on ([`ChronoError::StaleBody`] on use, as is removing
    /// a stale handle).
    ///
    /// A body that a joint or force element refers to is not removed:
    /// [`ChronoError::BodyInUse`] names them (joints cannot be removed, so a jointed body
    /// stays). Physics items that attached the body must be removed (or detach it) first:
    /// the system cannot see their references.
    ///
    /// Cost: O(1) for the bodies, plus rebuilding the caches keyed by body or collider:
    /// the collision world's colliders and broad phase (O(colliders)), the warm-start and
    /// SMC history caches (O(cached contacts)). Contacts of the removed body are dropped
    /// from these caches; the other contacts keep their warm start and history (except a
    /// pair whose collider ids swap order, which restarts cold). The contacts reported by
    /// [`contacts`](Self::contacts) are those of the last step until the next one.
    pub fn remove_body(&mut self, h: BodyHandle) -> Result<RigidBody> {
        let dense = self.bodies.try_index(h)?;
        let mut users: Vec<String> = (self.joints.iter().enumerate())
            .filter(|(_, j)| {
                let (a, b) = j.bodies();
                a == h || b == h
            })
            .map(|(i, j)| format!("joint {i} (\"{}\")", j.name()))
            .collect();
        users.extend(
            (self.force_elements.iter().enumerate())
                .filter(|(_, e)| e.body_handles().contains(&h))
                .map(|(i, e)| format!("force element {i} (\"{}\")", e.name())),
        );
        if !users.is_empty() {
            return Err(ChronoError::BodyInUse {
                handle: h,
                name: self.bodies[dense].name().to_string(),
                users,
            });
        }
        let (body, r) = self.bodies.remove(h)?;
        let moved = r.moved_from.map(|m| m as u32);
        let map = self.collision.remove_owner(r.removed as u32, moved);
        self.cache.remap(Some(&map), &Some);
        self.smc.remap_colliders(&map);
        if r.removed < self.contact_friction.len() {
            let last = self.bodies.len();
            self.contact_friction.resize(last + 1, None);
            self.contact_friction.swap_remove(r.removed);
        }
        // The last step's per-body buffers name old indices.
        self.contacts.clear();
        self.points.clear();
        self.proxy_contacts.clear();
        self.proxy_points.clear();
        self.loads.reset(&self.bodies);
        Ok(body)
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
