//! Collision detection: colliders (our [`Shape`](crate::shape::Shape)s on owners), a
//! sort-and-sweep broad phase and parry's narrow phase with persistent multi-point
//! manifolds.
//!
//! The [`System`](crate::system::System) owns one [`CollisionWorld`] and calls
//! [`CollisionWorld::detect`] each step with the world poses of the owners (rigid bodies).
//!
//! # Conventions
//!
//! - A [`ContactPoint`] joins collider A and collider B with `A < B` (by [`ColliderId`]).
//!   Its `normal` is the world unit normal **from A towards B**; `distance` is the signed
//!   gap along it (negative = penetration) and `point_b - point_a == distance * normal`.
//! - The envelope `delta` (m): contacts are reported while `distance < delta`, so the solver
//!   sees contacts a little before they close (NSC with `Phi/h` stabilization).
//! - [`ContactKey`] is stable across steps for the same touching feature pair (warm start,
//!   SMC history).
//! - Manifolds: a box resting on a box or on a half-space gives its 4 corner contacts.
//!
//! # Modules
//!
//! - `convert`: nalgebra <-> glam and [`Shape`](crate::shape::Shape) -> parry, the only
//!   place where both math libraries meet.
//! - `broad_phase`: sort-and-sweep of bounding boxes, half-spaces kept apart.
//! - `sphere_grid`: the uniform cell grid for scenes with many spheres (grains): sphere
//!   pairs found and computed on the grid, spheres against other shapes by grid queries.
//! - `ellipsoid`: the ellipsoid as a custom parry shape (support map, one-point feature
//!   map, exact point projection and ray cast), parry having none.
//! - `narrow_phase`: per-pair persistent state, analytic sphere fast paths, parry manifolds.
//! - `world`: [`CollisionWorld`] and [`Collider`].
//! - `removal`: removing owners in place (swap-remove of bodies).
//! - `proxy`: spheres and thick triangles of physics items against the body colliders.
//! - `mesh`: triangulation of shapes for visualization.

mod broad_phase;
mod contact;
pub(crate) mod convert;
pub(crate) mod ellipsoid;
pub(crate) mod mesh;
mod narrow_phase;
mod proxy;
mod removal;
mod sphere_grid;
mod world;

#[cfg(test)]
mod tests;

pub use contact::{ColliderId, ContactKey, ContactPoint, effective_radius};
pub use proxy::{CollisionProxy, ProxyContact, ProxyKey, ProxyShape};
pub use sphere_grid::GRID_MIN_SPHERES;
pub use world::{Collider, CollisionWorld};
