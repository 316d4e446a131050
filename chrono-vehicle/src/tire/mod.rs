//! Tires: a rigid tire (a cylinder collider, contact through the ordinary contact rows),
//! the TMeasy handling tire (a force element computing the contact forces from the
//! slips, see [`TMeasyTire`]) and the ANCF shell tire (a pressurized deformable carcass
//! mounted on the spindle, its own implicit block in the CCP, see [`ancf`]).
//!
//! A [`Tire`] is the serde description (`{"type": "Rigid", ...}`,
//! `{"type": "TMeasy", ...}` or `{"type": "ANCF", ...}`); the vehicle attaches it to a wheel (spindle) body whose spin
//! axis is the body's local **Y** axis (the [`Shape::Cylinder`] axis), pointing left in the
//! vehicle frame.

pub mod ancf;
mod tmeasy;
mod tmeasy_params;

pub use ancf::{AncfTireData, AncfTireModel};

pub use tmeasy::{TMeasyTire, TireOutput};
pub use tmeasy_params::{
    CurveAtLoad, SlipCurve, TMeasyParams, TireSize, characteristic, combined_force,
};

use chrono_core::math::{Isometry3, Vector3};
use chrono_core::{ContactMaterial, Shape};
use serde::{Deserialize, Serialize};

use crate::error::{Result, check_non_negative, check_positive};

/// A tire description (serde: internally tagged by `"type"`, `"Rigid"` or `"TMeasy"`).
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "type")]
// A description read once per vehicle; boxing the larger variant would only complicate it.
#[allow(clippy::large_enum_variant)]
pub enum Tire {
    /// A rigid cylinder touching the terrain through contact rows.
    Rigid(RigidTire),
    /// The TMeasy handling tire (forces from slips).
    TMeasy(TMeasyParams),
    /// The ANCF shell tire (a pressurized deformable carcass on the spindle).
    #[serde(rename = "ANCF")]
    Ancf(AncfTireData),
}

// By hand rather than derived: serde's internally tagged enums buffer the content and lose
// the path of a failing field inside it; this reads the tag, then the variant with its
// own path tracking, so an error names the field (`at `compliance`: ...`).
impl<'de> Deserialize<'de> for Tire {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        use serde::de::Error;
        let mut map = serde_json::Map::<String, serde_json::Value>::deserialize(d)?;
        let tag = match map.remove("type") {
            Some(serde_json::Value::String(t)) => t,
            Some(other) => {
                return Err(D::Error::custom(format!(
                    "at `type`: expected \"Rigid\", \"TMeasy\" or \"ANCF\", found {other}"
                )));
            }
            None => return Err(D::Error::missing_field("type")),
        };
        fn variant<T: serde::de::DeserializeOwned, E: Error>(
            map: serde_json::Map<String, serde_json::Value>,
        ) -> std::result::Result<T, E> {
            serde_path_to_error::deserialize(serde_json::Value::Object(map))
                .map_err(|e| E::custom(format!("at `{}`: {}", e.path(), e.inner())))
        }
        match tag.as_str() {
            "Rigid" => variant(map).map(Tire::Rigid),
            "TMeasy" => variant(map).map(Tire::TMeasy),
            "ANCF" => variant(map).map(Tire::Ancf),
            _ => Err(D::Error::custom(format!(
                "at `type`: unknown tire type `{tag}`, expected `Rigid`, `TMeasy` or `ANCF`"
            ))),
        }
    }
}

impl Tire {
    /// Check the description; errors name the field.
    pub fn validate(&self) -> Result<()> {
        match self {
            Tire::Rigid(t) => t.validate(),
            Tire::TMeasy(p) => p.validate(),
            Tire::Ancf(a) => a.validate(),
        }
    }

    /// Unloaded radius, m (the ANCF tire's before inflation).
    pub fn radius(&self) -> f64 {
        match self {
            Tire::Rigid(t) => t.radius,
            Tire::TMeasy(p) => p.radius,
            Tire::Ancf(a) => a.radius,
        }
    }

    /// Section width, m: the widest axial extent of the tire (a rigid or handling tire's
    /// `width`; an ANCF carcass' section circle where it bulges past its beads, plus the
    /// carcass thickness).
    pub fn section_width(&self) -> f64 {
        match self {
            Tire::Rigid(t) => t.width,
            Tire::TMeasy(p) => p.width,
            Tire::Ancf(a) => {
                let bulge = a
                    .geometry(Vector3::zeros())
                    .map(|g| {
                        if g.bead_angle > std::f64::consts::FRAC_PI_2 {
                            2.0 * g.section_radius
                        } else {
                            a.rim_width
                        }
                    })
                    .unwrap_or(a.rim_width);
                bulge + a.thickness
            }
        }
    }

    /// Tire mass, kg (a part of the vehicle's mass: on the wheel body for a rigid or
    /// handling tire, in the carcass' own nodes for an ANCF tire).
    pub fn mass(&self) -> f64 {
        match self {
            Tire::Rigid(t) => t.mass,
            Tire::TMeasy(p) => p.mass,
            Tire::Ancf(a) => a.mass,
        }
    }

    /// True if the tire's mass rides on the wheel body (rigid and handling tires); an ANCF
    /// carcass carries its own.
    pub fn on_spindle(&self) -> bool {
        !matches!(self, Tire::Ancf(_))
    }

    /// Principal moments of inertia of the tire about its center (wheel frame, spin axis
    /// Y) that the wheel body carries, kg m^2 (zero for an ANCF tire, whose carcass carries
    /// its own).
    pub fn inertia(&self) -> Vector3<f64> {
        let i = match self {
            Tire::Rigid(t) => t.inertia,
            Tire::TMeasy(p) => p.inertia,
            Tire::Ancf(_) => [0.0; 3],
        };
        Vector3::new(i[0], i[1], i[2])
    }
}

/// A rigid tire: a solid cylinder of `radius` and `width` about the wheel's spin axis
/// (local Y) with a contact material. It adds nothing but the collider: forces come from
/// the contact rows (friction cone with `friction`, optional rolling resistance).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RigidTire {
    /// Radius, m.
    pub radius: f64,
    /// Width, m.
    pub width: f64,
    /// Mass, kg.
    pub mass: f64,
    /// Principal moments of inertia `(Ixx, Iyy, Izz)` in the wheel frame (spin about Y),
    /// kg m^2.
    pub inertia: [f64; 3],
    /// Friction coefficient of the tread.
    pub friction: f64,
    /// Rolling friction coefficient (the contact material's `rolling_friction`), >= 0.
    #[serde(default)]
    pub rolling_friction: f64,
    /// NSC normal compliance of the contact, m/N (0 = rigid).
    #[serde(default)]
    pub compliance: f64,
    /// Young's modulus of the tread for SMC (penalty) contact, Pa (the contact's effective
    /// modulus combines it with the other body's: `1/E* = (1 - nu_1^2)/E_1 + (1 - nu_2^2)/E_2`,
    /// so a tire as soft as the grains halves the contact's stiffness, and stiffening the
    /// grains alone never makes the contact rigid). NSC ignores it. Default 2e7 Pa (the
    /// contact material's default, and Chrono's rigid-tire data).
    #[serde(default = "default_tread_young_modulus")]
    pub young_modulus: f64,
}

fn default_tread_young_modulus() -> f64 {
    ContactMaterial::default().young_modulus
}

impl RigidTire {
    /// The HMMWV tire as a rigid cylinder (radius 0.467 m, width 0.254 m, mass 37.6 kg,
    /// inertia (3.84, 6.69, 3.84) kg m^2: Chrono's HMMWV data, our reference notes sec. 7),
    /// friction 0.9 (dry road).
    pub fn hmmwv() -> Self {
        Self {
            radius: 0.467,
            width: 0.254,
            mass: 37.6,
            inertia: [3.84, 6.69, 3.84],
            friction: 0.9,
            rolling_friction: 0.0,
            compliance: 0.0,
            young_modulus: default_tread_young_modulus(),
        }
    }

    /// Check the fields; errors name them (`rigid_tire.radius` ...).
    pub fn validate(&self) -> Result<()> {
        check_positive("rigid_tire.radius", self.radius)?;
        check_positive("rigid_tire.width", self.width)?;
        check_positive("rigid_tire.mass", self.mass)?;
        for (k, name) in ["x", "y", "z"].iter().enumerate() {
            check_positive(&format!("rigid_tire.inertia.{name}"), self.inertia[k])?;
        }
        check_non_negative("rigid_tire.friction", self.friction)?;
        check_non_negative("rigid_tire.rolling_friction", self.rolling_friction)?;
        check_non_negative("rigid_tire.compliance", self.compliance)?;
        check_positive("rigid_tire.young_modulus", self.young_modulus)?;
        Ok(())
    }

    /// The collider shape: a [`Shape::Cylinder`] with its axis along local Y.
    pub fn shape(&self) -> Shape {
        Shape::Cylinder {
            half_length: 0.5 * self.width,
            radius: self.radius,
        }
    }

    /// The tread material (friction, rolling friction, NSC compliance, SMC modulus).
    pub fn material(&self) -> ContactMaterial {
        ContactMaterial {
            friction: self.friction,
            rolling_friction: self.rolling_friction,
            compliance: self.compliance,
            young_modulus: self.young_modulus,
            ..ContactMaterial::default()
        }
    }

    /// `(shape, local pose, material)` to attach to the wheel body (identity pose: the
    /// wheel body's origin is the wheel center and its Y axis the spin axis), e.g. with
    /// [`RigidBodyBuilder::collider`](chrono_core::RigidBodyBuilder::collider).
    pub fn collider(&self) -> Result<(Shape, Isometry3<f64>, ContactMaterial)> {
        self.validate()?;
        Ok((self.shape(), Isometry3::identity(), self.material()))
    }
}
