//! Granular material: grain packings ([`LatticeFill`] in a [`Region`]), a seeded random
//! generator ([`Rng`]), helpers that put grains and containers into a
//! [`System`], and the scenes built from them:
//!
//! - [`bed`]: a bed poured from a loose lattice and settled ([`GrainBed`]);
//! - [`silo`]: a flat-bottomed silo with an orifice and the recycling of its discharge
//!   ([`Silo`], [`Recycler`]);
//! - [`shear_box`]: the direct shear box and the reduction of its curve ([`ShearBox`]);
//! - [`shear_test`]: the direct shear test in that box (pour, consolidation, shear at
//!   constant speed, the read-out by bins of displacement: [`ShearTest`], [`ShearRun`]);
//! - [`column`](mod@column): a granular column released from behind a gate in a slab, its runout
//!   and final height ([`GranularColumn`], [`ColumnRun`]);
//! - [`heap`]: a heap left on a plate in a slot after discharge over both edges, and its
//!   angle of repose ([`HeapSlot`], [`Heap`]);
//! - [`impact`]: a ball dropped into a settled bed, and its penetration ([`ImpactBed`],
//!   [`BallDrop`]);
//! - [`wheel`]: a rigid wheel driven at fixed slip on a granular slab, its sinkage,
//!   drawbar pull and torque ([`WheelBin`], [`WheelRun`]);
//! - [`probe`]: measurements on a bed (surface height, bulk density, heap flank angles,
//!   grain forces on a body, penetration).
//!
//! Grains are ordinary dynamic rigid bodies with one sphere collider (or several for a
//! clump), so both contact methods apply: NSC (DEM-C, complementarity) and SMC (DEM-P,
//! penalty), chosen by [`SystemSettings::contact_method`](crate::SystemSettings). From
//! [`GRID_MIN_SPHERES`](crate::collision::GRID_MIN_SPHERES) spheres on, the collision
//! world finds sphere pairs on a uniform cell grid.

pub mod bed;
pub mod column;
mod fill;
pub mod heap;
pub mod impact;
pub mod kicked_box;
pub mod probe;
pub mod shear_box;
pub mod shear_test;
pub mod silo;
pub mod wheel;

/// The seeded generator, re-exported from its old place ([`crate::rng::Rng`]).
pub use crate::rng::Rng;
pub use bed::{Bed, GrainBed, Kick, Settle, Settled};
pub use column::{ColumnRun, ColumnScene, Deposit, GranularColumn};
pub use fill::{Grain, LatticeFill, Region};
pub use heap::{Heap, HeapScene, HeapSlot};
pub use impact::{BallDrop, ImpactBed, Penetration};
pub use kicked_box::KickedBox;
pub use shear_box::{ShearBox, ShearBoxBodies};
pub use shear_test::{ShearRun, ShearTest};
pub use silo::{Recycler, Silo, SiloBodies};
pub use wheel::{PreparedBed, WheelBin, WheelRun};

use nalgebra::{Isometry3, Vector3};

use crate::body::{BodyHandle, RigidBodyBuilder};
use crate::error::{ChronoError, Result, check_positive};
use crate::material::ContactMaterial;
use crate::shape::Shape;
use crate::system::{ContactMethod, System};

/// The time step of a granular scene (s): `h` if it is > 0, else 1 ms for NSC and the SMC
/// stability limit of `sys` ([`System::smc_max_step`], 1e-4 s without grains) for SMC.
pub fn step_size(h: f64, method: ContactMethod, sys: &System) -> f64 {
    if h > 0.0 {
        h
    } else if method == ContactMethod::Nsc {
        1e-3
    } else {
        sys.smc_max_step().map(|(h, _)| h).unwrap_or(1e-4)
    }
}

/// Add each grain as a dynamic sphere of `density` (kg/m^3) and `material`; returns the
/// handles in grain order.
pub fn add_grains(
    sys: &mut System,
    grains: &[Grain],
    density: f64,
    material: ContactMaterial,
) -> Result<Vec<BodyHandle>> {
    check_positive("grain density", density)?;
    grains
        .iter()
        .map(|g| {
            let s = Shape::Sphere { radius: g.radius };
            sys.add_body(
                RigidBodyBuilder::dynamic()
                    .mass_from_shape(&s, density)?
                    .position(g.center)
                    .collider(s, Isometry3::identity(), material),
            )
        })
        .collect()
}

/// A fixed open box `[lower, upper]`: a floor at `lower.z` and four walls, as half-spaces
/// (their solid outside the box), on one fixed body named `name`.
pub fn add_box_container(
    sys: &mut System,
    name: &str,
    lower: Vector3<f64>,
    upper: Vector3<f64>,
    material: ContactMaterial,
) -> Result<BodyHandle> {
    if (0..3).any(|a| upper[a] <= lower[a]) {
        return Err(ChronoError::invalid(
            "container.upper",
            format!("{upper:?}"),
            "must exceed container.lower on every axis",
        ));
    }
    let mut b = RigidBodyBuilder::fixed().name(name);
    let walls = [
        (Vector3::z(), lower),
        (Vector3::x(), lower),
        (-Vector3::x(), upper),
        (Vector3::y(), lower),
        (-Vector3::y(), upper),
    ];
    for (normal, at) in walls {
        b = b.collider(
            Shape::HalfSpace { normal },
            Isometry3::translation(at.x, at.y, at.z),
            material,
        );
    }
    sys.add_body(b)
}

/// A fixed vertical cylindrical wall of inner `radius` (m) around the axis through `base`,
/// approximated by a regular polygon of `sides` half-spaces whose inscribed circle is the
/// cylinder (their solid outside), on one fixed body named `name`. No floor.
pub fn add_cylinder_wall(
    sys: &mut System,
    name: &str,
    base: Vector3<f64>,
    radius: f64,
    sides: usize,
    material: ContactMaterial,
) -> Result<BodyHandle> {
    check_positive("container.radius", radius)?;
    if sides < 3 {
        return Err(ChronoError::invalid(
            "container.sides",
            sides,
            "must be >= 3",
        ));
    }
    let mut b = RigidBodyBuilder::fixed().name(name);
    for k in 0..sides {
        let a = std::f64::consts::TAU * k as f64 / sides as f64;
        let out = Vector3::new(a.cos(), a.sin(), 0.0);
        let at = base + out * radius;
        b = b.collider(
            Shape::HalfSpace { normal: -out },
            Isometry3::translation(at.x, at.y, at.z),
            material,
        );
    }
    sys.add_body(b)
}
