//! Rigid terrains: what a tire model asks of the ground (height, normal, friction at a
//! horizontal position) and the collision geometry of the ground for rigid tires.
//!
//! - [`FlatTerrain`]: the plane `z = height` with one friction coefficient;
//! - [`HeightmapTerrain`]: heights on a regular grid (from a function or a text file),
//!   bilinear in between;
//! - [`GranularPatch`]: a bed of grains under the vehicle that moves with it (rigid tires
//!   only: the grains are bodies in the system's contact problem).
//!
//! A handling tire ([`crate::tire::TMeasyTire`]) queries the terrain through the
//! [`Terrain`] trait; a rigid tire touches the collider that
//! [`Terrain::add_to_system`] adds to a [`System`] through the ordinary contact rows.
//! World frame: Z up, SI units.

mod granular;
mod heightmap;

pub use granular::{GranularPatch, GranularPatchParams};
pub use heightmap::HeightmapTerrain;

use chrono_core::math::{Isometry3, Vector3};
use chrono_core::{BodyHandle, ContactMaterial, RigidBodyBuilder, Shape, System};
use serde::{Deserialize, Serialize};

use crate::error::{Result, check_finite, check_non_negative};

/// The ground as seen by a tire model. Positions are world `(x, y)` in meters.
pub trait Terrain: Send + Sync {
    /// Height `z` (m) of the surface above the point `(x, y)`.
    fn height(&self, x: f64, y: f64) -> f64;

    /// Unit upward normal of the surface at `(x, y)`.
    fn normal(&self, x: f64, y: f64) -> Vector3<f64>;

    /// Coulomb friction coefficient of the surface at `(x, y)` (dimensionless).
    fn friction(&self, x: f64, y: f64) -> f64;

    /// Add the terrain's rigid collision geometry to `sys` as a fixed body with `material`
    /// (its friction should normally be [`Terrain::friction`]); returns the body.
    fn add_to_system(&self, sys: &mut System, material: ContactMaterial) -> Result<BodyHandle>;
}

/// The horizontal plane `z = height`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct FlatTerrain {
    /// Height of the plane, m.
    pub height: f64,
    /// Friction coefficient, >= 0.
    pub friction: f64,
}

impl FlatTerrain {
    /// The plane `z = height` with friction coefficient `friction`. Errors name the field
    /// (`flat_terrain.height` not finite, `flat_terrain.friction` negative).
    pub fn new(height: f64, friction: f64) -> Result<Self> {
        let t = Self { height, friction };
        t.validate()?;
        Ok(t)
    }

    /// Check the fields (after deserializing).
    pub fn validate(&self) -> Result<()> {
        check_finite("flat_terrain.height", self.height)?;
        check_non_negative("flat_terrain.friction", self.friction)?;
        Ok(())
    }
}

impl Terrain for FlatTerrain {
    fn height(&self, _x: f64, _y: f64) -> f64 {
        self.height
    }

    fn normal(&self, _x: f64, _y: f64) -> Vector3<f64> {
        Vector3::z()
    }

    fn friction(&self, _x: f64, _y: f64) -> f64 {
        self.friction
    }

    /// A fixed body at `(0, 0, height)` with a [`Shape::HalfSpace`] of normal `+Z`.
    fn add_to_system(&self, sys: &mut System, material: ContactMaterial) -> Result<BodyHandle> {
        self.validate()?;
        let b = RigidBodyBuilder::fixed()
            .name("flat terrain")
            .position(Vector3::new(0.0, 0.0, self.height))
            .collider(
                Shape::HalfSpace {
                    normal: Vector3::z(),
                },
                Isometry3::identity(),
                material,
            );
        Ok(sys.add_body(b)?)
    }
}
