//! The collision world: colliders attached to owners (rigid bodies), and one `detect` per
//! step that runs the broad phase, keeps per-pair state and runs the narrow phase.

use parry3d_f64::bounding_volume::BoundingVolume;
use parry3d_f64::math::{Pose, Vector};
use parry3d_f64::shape::SharedShape;
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};

use super::broad_phase::{Bound, SweepAndPrune};
use super::contact::{ColliderId, ContactPoint};
use super::convert::{pose_to_glam, to_parry, vec_to_glam};
use super::narrow_phase::{PairKind, PairState};
use super::proxy::ProxyScratch;
use super::sphere_grid::{GRID_MIN_SPHERES, SphereGrid};
use crate::error::{ChronoError, Result, check_non_negative};
use crate::material::ContactMaterial;
use crate::math::Isometry3;
use crate::shape::Shape;

/// Below this many candidate pairs the narrow phase runs serially.
pub(crate) const PARALLEL_MIN_PAIRS: usize = 128;
/// Pairs per rayon task.
const PARALLEL_CHUNK: usize = 32;
/// From this many colliders on, poses and bounds are computed in parallel.
const PARALLEL_MIN_COLLIDERS: usize = 1024;
/// Colliders per rayon task.
const COLLIDER_CHUNK: usize = 512;

/// Which fast path a collider can take.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum ColliderKind {
    /// A sphere (analytic contacts against spheres and half-spaces).
    Sphere {
        /// Radius (m).
        radius: f64,
    },
    /// A half-space with this unit outward normal in the collider's local frame.
    HalfSpace {
        /// Unit normal.
        normal: Vector,
    },
    /// Anything else (parry manifolds).
    Other,
}

/// A shape attached to an owner (a rigid body) at a local pose, with a material.
#[derive(Clone)]
pub struct Collider {
    pub(super) owner: u32,
    local_pose: Isometry3<f64>,
    material: ContactMaterial,
    shape: Shape,
    /// The parry shape, built once.
    pub(crate) parry: SharedShape,
    /// Pose of the parry shape in the owner frame (local pose times the shape offset).
    pub(crate) parry_local: Pose,
    pub(crate) kind: ColliderKind,
    /// A sphere whose parry pose in the owner frame is the identity (its world pose is
    /// the owner's).
    pub(crate) local_identity: bool,
    /// Triangle mesh or height field (features carry a triangle index).
    pub(crate) composite: bool,
}

impl std::fmt::Debug for Collider {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Collider")
            .field("owner", &self.owner)
            .field("local_pose", &self.local_pose)
            .field("material", &self.material)
            .field("shape", &self.shape)
            .finish_non_exhaustive()
    }
}

impl Collider {
    /// The owner (rigid body index) of this collider.
    pub fn owner(&self) -> u32 {
        self.owner
    }

    /// Pose of the shape in the owner's frame.
    pub fn local_pose(&self) -> &Isometry3<f64> {
        &self.local_pose
    }

    /// The surface material.
    pub fn material(&self) -> ContactMaterial {
        self.material
    }

    /// The shape (local frame).
    pub fn shape(&self) -> &Shape {
        &self.shape
    }
}

/// Colliders and the persistent state of collision detection.
///
/// The broad phase is a sort-and-sweep (see the `broad_phase` module docs); candidate pairs
/// keep parry's contact manifolds from one [`detect`](Self::detect) to the next. Buffers are
/// reused, so a steady scene does not allocate in `detect` (except inside parry).
pub struct CollisionWorld {
    pub(super) envelope: f64,
    pub(super) colliders: Vec<Collider>,
    /// Excluded owner pairs `(min, max)`, sorted.
    pub(super) excluded: Vec<(u32, u32)>,
    /// World poses of the parry shapes (last `detect`).
    pub(super) poses: Vec<Pose>,
    /// Broad-phase bounds (last `detect`).
    pub(super) bounds: Vec<Bound>,
    sap: SweepAndPrune,
    candidates: Vec<(u32, u32)>,
    /// Live pair states, sorted by `(a, b)`.
    pub(super) pairs: Vec<PairState>,
    /// The other buffer for `pairs` (double buffering).
    pub(super) next_pairs: Vec<PairState>,
    /// Dropped pair states kept for their buffers.
    pub(super) spare: Vec<PairState>,
    /// Buffers of `detect_proxies`.
    pub(super) proxy_scratch: ProxyScratch,
    /// Number of sphere colliders.
    pub(super) spheres: usize,
    /// Use the sphere grid from this many sphere colliders on.
    grid_min_spheres: usize,
    /// The sphere grid (broad and narrow phase of sphere pairs).
    pub(super) grid: SphereGrid,
    /// Whether the last `detect` used the grid.
    used_grid: bool,
    /// Wall time of the last `detect`: broad phase, narrow phase (s).
    timing: (f64, f64),
    /// Whether the colliders are sorted by owner (true while they are added in owner
    /// order, as [`System`](crate::system::System) does); removal relies on it.
    pub(super) owner_sorted: bool,
    /// One past the largest owner index of the colliders, `None` when unknown (colliders
    /// were added or removed since it was computed): with it, `detect` checks the owners
    /// against the pose slice without a pass over the colliders.
    pub(super) owner_bound: Option<usize>,
    /// Per collider: owner and, for a sphere at its owner's origin, its radius (NaN for
    /// the others): what the bounds of grains need, 16 bytes instead of the whole
    /// collider. Rebuilt when stale (removals) or when colliders were added.
    pub(super) hot: Vec<(u32, f64)>,
    pub(super) hot_stale: bool,
}

impl std::fmt::Debug for CollisionWorld {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("CollisionWorld")
            .field("envelope", &self.envelope)
            .field("colliders", &self.colliders.len())
            .field("excluded", &self.excluded)
            .field("pairs", &self.pairs.len())
            .finish_non_exhaustive()
    }
}

impl CollisionWorld {
    /// An empty world. `envelope` (m, >= 0): contacts are reported when the signed
    /// distance is `< envelope` (so 0 reports only penetrating pairs).
    pub fn new(envelope: f64) -> Result<Self> {
        check_non_negative("collision.envelope", envelope)?;
        Ok(Self {
            envelope,
            colliders: Vec::new(),
            excluded: Vec::new(),
            poses: Vec::new(),
            bounds: Vec::new(),
            sap: SweepAndPrune::default(),
            candidates: Vec::new(),
            pairs: Vec::new(),
            next_pairs: Vec::new(),
            spare: Vec::new(),
            proxy_scratch: ProxyScratch::default(),
            spheres: 0,
            grid_min_spheres: GRID_MIN_SPHERES,
            grid: SphereGrid::default(),
            used_grid: false,
            timing: (0.0, 0.0),
            owner_sorted: true,
            owner_bound: Some(0),
            hot: Vec::new(),
            hot_stale: false,
        })
    }

    /// The envelope (m).
    pub fn envelope(&self) -> f64 {
        self.envelope
    }

    /// Change the envelope (m, >= 0).
    pub fn set_envelope(&mut self, envelope: f64) -> Result<()> {
        self.envelope = check_non_negative("collision.envelope", envelope)?;
        Ok(())
    }

    /// Add a collider owned by `owner` (a rigid body index into the arrays passed to
    /// [`detect`](Self::detect)), placed at `local_pose` in the owner's frame. The shape
    /// and material are validated and the parry shape is built here, once.
    pub fn add_collider(
        &mut self,
        owner: u32,
        shape: &Shape,
        local_pose: Isometry3<f64>,
        material: ContactMaterial,
    ) -> Result<ColliderId> {
        shape.validate("collider.shape")?;
        material.validate()?;
        let finite = local_pose
            .translation
            .vector
            .iter()
            .chain(local_pose.rotation.coords.iter())
            .all(|c| c.is_finite());
        if !finite {
            return Err(ChronoError::invalid(
                "collider.local_pose",
                local_pose,
                "must be finite",
            ));
        }
        let id = u32::try_from(self.colliders.len()).map_err(|_| {
            ChronoError::invalid("collider", self.colliders.len(), "too many colliders")
        })?;
        let parry = to_parry(shape, "collider.shape")?;
        if self.colliders.last().is_some_and(|c| c.owner > owner) {
            self.owner_sorted = false;
        }
        let kind = match shape {
            Shape::Sphere { radius } => {
                self.spheres += 1;
                ColliderKind::Sphere { radius: *radius }
            }
            Shape::HalfSpace { normal } => ColliderKind::HalfSpace {
                normal: vec_to_glam(&normal.normalize()),
            },
            _ => ColliderKind::Other,
        };
        let parry_local = pose_to_glam(&(local_pose * parry.offset));
        self.owner_bound = self.owner_bound.map(|b| b.max(owner as usize + 1));
        self.colliders.push(Collider {
            owner,
            local_pose,
            material,
            shape: shape.clone(),
            parry: parry.shape,
            parry_local,
            local_identity: matches!(kind, ColliderKind::Sphere { .. })
                && parry_local == Pose::IDENTITY,
            kind,
            composite: matches!(shape, Shape::TriMesh { .. } | Shape::HeightField { .. }),
        });
        Ok(ColliderId(id))
    }

    /// The collider `id`, if it exists.
    pub fn collider(&self, id: ColliderId) -> Option<&Collider> {
        self.colliders.get(id.0 as usize)
    }

    /// All colliders, indexed by [`ColliderId`].
    pub fn colliders(&self) -> &[Collider] {
        &self.colliders
    }

    /// Number of colliders.
    pub fn len(&self) -> usize {
        self.colliders.len()
    }

    /// True if there is no collider.
    pub fn is_empty(&self) -> bool {
        self.colliders.is_empty()
    }

    /// Never report contacts between the colliders of `owner_a` and those of `owner_b`
    /// (e.g. two bodies connected by a joint). Symmetric; idempotent.
    pub fn exclude_pair(&mut self, owner_a: u32, owner_b: u32) {
        let key = (owner_a.min(owner_b), owner_a.max(owner_b));
        if let Err(at) = self.excluded.binary_search(&key) {
            self.excluded.insert(at, key);
        }
    }

    /// Undo [`exclude_pair`](Self::exclude_pair): contacts between the two owners are
    /// reported again. Symmetric; a pair that is not excluded is left alone.
    pub fn include_pair(&mut self, owner_a: u32, owner_b: u32) {
        let key = (owner_a.min(owner_b), owner_a.max(owner_b));
        if let Ok(at) = self.excluded.binary_search(&key) {
            self.excluded.remove(at);
        }
    }

    /// Use the sphere grid (see the `sphere_grid` module) when the world holds at least
    /// `n` sphere colliders (default [`GRID_MIN_SPHERES`](super::GRID_MIN_SPHERES)); 0
    /// always, `usize::MAX` never. The contacts found are the same either way, only their
    /// order differs.
    pub fn set_grid_min_spheres(&mut self, n: usize) {
        self.grid_min_spheres = n;
    }

    /// Set the Verlet skin of the sphere grid as a fraction `skin` of the largest sphere
    /// radius `r_max` (finite and >= 0; default 0): the grid keeps the sphere pairs within
    /// `2 r_max + envelope + skin r_max` and rebuilds the list only once a sphere has moved
    /// more than `skin r_max / 2` since the last build. The contacts found (and their
    /// order) do not depend on it; a skin pays where spheres move little per step (SMC).
    pub fn set_sphere_skin(&mut self, skin: f64) -> Result<()> {
        check_non_negative("collision.sphere_skin", skin)?;
        self.grid.set_skin(skin);
        Ok(())
    }

    /// The Verlet skin of the sphere grid, a fraction of the largest sphere radius
    /// ([`set_sphere_skin`](Self::set_sphere_skin)).
    pub fn sphere_skin(&self) -> f64 {
        self.grid.skin()
    }

    /// Number of times the sphere grid has binned the spheres and searched their pairs
    /// (once per [`detect`](Self::detect) without a skin, less with one).
    pub fn sphere_grid_rebuilds(&self) -> u64 {
        self.grid.rebuilds()
    }

    /// Wall time (s) of the last [`detect`](Self::detect): `(broad phase, narrow phase)`
    /// (bounds, grid binning, pair search and pair bookkeeping; then the contact points).
    pub fn last_timing(&self) -> (f64, f64) {
        self.timing
    }

    /// Whether the last [`detect`](Self::detect) used the sphere grid.
    pub fn used_grid(&self) -> bool {
        self.used_grid
    }

    /// Number of live candidate pairs (after filtering) of the last `detect`.
    #[cfg(test)]
    pub(crate) fn num_pairs(&self) -> usize {
        self.pairs.len()
    }

    /// Whether the owner pair was excluded with [`exclude_pair`](Self::exclude_pair).
    pub fn is_pair_excluded(&self, owner_a: u32, owner_b: u32) -> bool {
        self.excluded
            .binary_search(&(owner_a.min(owner_b), owner_a.max(owner_b)))
            .is_ok()
    }

    /// Find all contacts of this step, written into `out` (cleared first).
    ///
    /// `owner_poses[owner]` is the world pose of each owner, `owner_active[owner]` is false
    /// for fixed or kinematic owners. Skipped pairs: two colliders of the same owner, two
    /// inactive owners, and excluded owner pairs. Output order is deterministic (by pair
    /// `(collider_a, collider_b)`, then parry's order within a pair; with the sphere grid,
    /// the sphere–sphere contacts follow in the grid's order) and does not depend on the
    /// number of threads. Errors: an owner out of range of either slice, a non-finite
    /// owner pose, or a pair parry cannot handle ([`ChronoError::Collision`]); on error
    /// `out` holds a partial result.
    pub fn detect(
        &mut self,
        owner_poses: &[Isometry3<f64>],
        owner_active: &[bool],
        out: &mut Vec<ContactPoint>,
    ) -> Result<()> {
        out.clear();
        let t0 = std::time::Instant::now();
        self.update_bounds(owner_poses, owner_active)?;
        self.used_grid = self.spheres > 0 && self.spheres >= self.grid_min_spheres;
        if self.used_grid {
            self.grid.candidates(
                &self.colliders,
                &self.poses,
                &self.bounds,
                self.envelope,
                &mut self.candidates,
            )?;
        } else {
            self.sap.find_pairs(&self.bounds, &mut self.candidates);
        }
        self.update_pairs(owner_active);
        let t1 = std::time::Instant::now();
        self.timing = ((t1 - t0).as_secs_f64(), 0.0);

        let (colliders, poses, envelope) = (&self.colliders, &self.poses, self.envelope);
        if self.pairs.len() >= PARALLEL_MIN_PAIRS {
            self.pairs
                .par_iter_mut()
                .with_min_len(PARALLEL_CHUNK)
                .for_each(|p| p.update(colliders, poses, envelope));
        } else {
            self.pairs
                .iter_mut()
                .for_each(|p| p.update(colliders, poses, envelope));
        }
        for p in &mut self.pairs {
            if let Some(e) = p.error.take() {
                return Err(*e);
            }
            out.extend_from_slice(&p.contacts);
        }
        if self.used_grid {
            self.grid.sphere_contacts(
                &self.colliders,
                owner_active,
                &self.excluded,
                self.envelope,
                out,
            )?;
        }
        self.timing.1 = t1.elapsed().as_secs_f64();
        Ok(())
    }

    /// World poses of the parry shapes and their broad-phase bounds.
    fn update_bounds(
        &mut self,
        owner_poses: &[Isometry3<f64>],
        owner_active: &[bool],
    ) -> Result<()> {
        let half = 0.5 * self.envelope;
        // The first bad collider in order (deterministic): an owner out of range.
        let n_owners = owner_poses.len().min(owner_active.len());
        let bound = *self.owner_bound.get_or_insert_with(|| {
            (self.colliders.iter())
                .map(|c| c.owner as usize + 1)
                .max()
                .unwrap_or(0)
        });
        if bound > n_owners
            && let Some((i, c)) =
                (self.colliders.iter().enumerate()).find(|(_, c)| c.owner as usize >= n_owners)
        {
            let o = c.owner as usize;
            let field = if o >= owner_poses.len() {
                "owner_poses"
            } else {
                "owner_active"
            };
            return Err(ChronoError::UnknownHandle {
                kind: "body",
                index: o,
                field: format!("{field} (owner of collider {i})"),
            });
        }
        if self.hot_stale || self.hot.len() != self.colliders.len() {
            self.hot.clear();
            self.hot.extend(self.colliders.iter().map(|c| {
                let r = match c.kind {
                    ColliderKind::Sphere { radius } if c.local_identity => radius,
                    _ => f64::NAN,
                };
                (c.owner, r)
            }));
            self.hot_stale = false;
        }
        let colliders = &self.colliders;
        let one = |(i, &(owner, radius)): (usize, &(u32, f64))| -> (Pose, Bound) {
            let g = pose_to_glam(&owner_poses[owner as usize]);
            if !radius.is_nan() && g.is_finite() {
                // A sphere at its owner's origin: the owner's pose, a cube bound (the same
                // values as the general path below).
                let r = Vector::splat(radius + half);
                let bound = Bound::Box(parry3d_f64::bounding_volume::Aabb::new(
                    g.translation - r,
                    g.translation + r,
                ));
                return (g, bound);
            }
            let c = &colliders[i];
            if !g.is_finite() {
                // Reported below; no bound from a non-finite pose.
                return (
                    g,
                    Bound::Box(parry3d_f64::bounding_volume::Aabb::new(
                        Vector::ZERO,
                        Vector::ZERO,
                    )),
                );
            }
            // A sphere at its owner's origin has the owner's pose (skip the composition).
            let pose = if c.local_identity {
                g
            } else {
                g * c.parry_local
            };
            let bound = match c.kind {
                ColliderKind::Sphere { radius } => {
                    let r = Vector::splat(radius + half);
                    Bound::Box(parry3d_f64::bounding_volume::Aabb::new(
                        pose.translation - r,
                        pose.translation + r,
                    ))
                }
                ColliderKind::HalfSpace { normal } => {
                    let n = pose.rotation * normal;
                    Bound::HalfSpace {
                        origin: pose.translation + n * half,
                        normal: n,
                    }
                }
                _ => Bound::Box(c.parry.compute_aabb(&pose).loosened(half)),
            };
            (pose, bound)
        };
        self.poses.clear();
        self.bounds.clear();
        // Whether some pose is not finite (a flag: the result does not depend on the
        // order the threads set it in); the first such collider is then found in order.
        let any_bad = AtomicBool::new(false);
        let one = |c| {
            let (p, b) = one(c);
            if !p.is_finite() {
                any_bad.store(true, Ordering::Relaxed);
            }
            (p, b)
        };
        if self.colliders.len() >= PARALLEL_MIN_COLLIDERS {
            let it = (self.hot.par_iter().enumerate())
                .with_min_len(COLLIDER_CHUNK)
                .map(one);
            it.unzip_into_vecs(&mut self.poses, &mut self.bounds);
        } else {
            for c in self.hot.iter().enumerate() {
                let (p, b) = one(c);
                self.poses.push(p);
                self.bounds.push(b);
            }
        }
        if !any_bad.into_inner() {
            return Ok(());
        }
        // The first collider (in order) whose owner's pose is not finite.
        if let Some(i) = self.poses.iter().position(|p| !p.is_finite()) {
            let o = self.colliders[i].owner as usize;
            return Err(ChronoError::invalid(
                format!("owner_poses[{o}]"),
                owner_poses[o],
                "must be finite",
            ));
        }
        Ok(())
    }

    /// Filter the candidates and match them with last step's pair states (both sorted).
    fn update_pairs(&mut self, owner_active: &[bool]) {
        let mut old = std::mem::take(&mut self.pairs);
        self.pairs = std::mem::take(&mut self.next_pairs);
        self.pairs.clear();
        let mut old_it = old.drain(..).peekable();
        for &(a, b) in &self.candidates {
            let (ca, cb) = (&self.colliders[a as usize], &self.colliders[b as usize]);
            let (oa, ob) = (ca.owner, cb.owner);
            if oa == ob || !(owner_active[oa as usize] || owner_active[ob as usize]) {
                continue;
            }
            if self
                .excluded
                .binary_search(&(oa.min(ob), oa.max(ob)))
                .is_ok()
            {
                continue;
            }
            while let Some(stale) = old_it.next_if(|s| (s.a, s.b) < (a, b)) {
                self.spare.push(stale);
            }
            let state = match old_it.next_if(|s| (s.a, s.b) == (a, b)) {
                Some(s) => s,
                None => {
                    let kind = PairKind::of(ca, cb);
                    match self.spare.pop() {
                        Some(mut s) => {
                            s.reset(a, b, kind);
                            s
                        }
                        None => PairState::new(a, b, kind),
                    }
                }
            };
            self.pairs.push(state);
        }
        self.spare.extend(old_it);
        self.next_pairs = old;
    }
}
