//! The ANCF shell tire as a vehicle tire: chrono-fea's pressurized toroidal carcass
//! ([`TireMesh`], inflated by [`InflatedTire`]) mounted on a wheel's spindle body by bead
//! attachment rows, stepped implicitly inside the vehicle's CCP as its own block, touching
//! the terrain through the ordinary contact rows of its node spheres.
//!
//! # Geometry from the tire's size
//!
//! The carcass is the open torus of [`TireMesh`]: ring radius `R_c`, section radius `a`,
//! bead angle `phi_b` (from the tread). A tire is given by the outer radius of its tread
//! `r_o`, the rim (bead seat) radius `r_r`, the distance between the beads `w` and the
//! carcass thickness `t`. With the mid surface's outer radius `R_m = r_o - t / 2`, the three
//! conditions `R_c + a = R_m`, `R_c + a cos phi_b = r_r` and `a sin phi_b = w / 2` give
//!
//! ```text
//! tan(phi_b / 2) = (R_m - r_r) / (w / 2),   a = (w / 2) / sin phi_b,   R_c = R_m - a
//! ```
//!
//! (`(1 - cos phi) / sin phi = tan(phi / 2)`). The carcass' density is set so that the
//! mesh's mass is the tire's `mass` exactly (a uniform shell: tread and sidewall alike).
//!
//! # The HMMWV tire ([`AncfTireData::hmmwv`])
//!
//! Size from Project Chrono's HMMWV ANCF tire (`HMMWV_ANCFTire`, as summarized in our
//! reference notes, sec. 6 "ANCF tire"): free radius 0.4673 m, rim radius 0.2683 m, rim
//! width 0.254 m, inflation 200 kPa; mass 37.6 kg (the same data's rigid and TMeasy
//! HMMWV tire, sec. 7). Chrono's carcass is a layered orthotropic shell (bead, sidewall and
//! tread ply stacks with steel cords); chrono-fea's shell is isotropic, so the carcass here
//! is one effective isotropic layer: thickness 15 mm, Young's modulus 1e8 Pa, Poisson 0.3
//! (**assumed**, the values of chrono-fea's tire cases scaled to this size; no published
//! load-deflection curve of this tire was found, see docs/validation-vehicle.md).
//! No structural damping by default (`damping` 0): chrono-fea's damping `beta K` acts on
//! the whole tangent, whose stress stiffness does not vanish on a rigid turn of the
//! prestressed carcass, so it brakes the rolling tire (0.005 s, `fea-tire-rolling`'s value,
//! let the HMMWV reach 12.0 km/h in 3 s against 23.4 without it and 29.5 on rigid tires:
//! docs/validation-vehicle.md); the static load case settles at 4 ms without it. Friction
//! 0.9 (the rigid tire's).

use chrono_core::body::BodyHandle;
use chrono_core::item::ItemHandle;
use chrono_core::math::{Isometry3, Vector3};
use chrono_core::{ContactMaterial, System};
use chrono_fea::{
    BeadMount, InflatedTire, ShellItem, ShellMaterial, TireGeometry, TireMesh, mount_on_rim_at,
};
use serde::{Deserialize, Serialize};

use crate::error::{Result, VehicleError, check_non_negative, check_positive};

/// An ANCF shell tire's description (see the module docs).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AncfTireData {
    /// Free outer radius of the tread (outer face of the carcass), m.
    pub radius: f64,
    /// Rim (bead seat) radius, m: the bead rings' mid surface sits there.
    pub rim_radius: f64,
    /// Rim width: the distance between the two bead rings, m.
    pub rim_width: f64,
    /// Carcass thickness, m.
    pub thickness: f64,
    /// Carcass mass, kg (sets the shell's density).
    pub mass: f64,
    /// Effective Young's modulus of the isotropic carcass, Pa.
    pub young: f64,
    /// Poisson's ratio of the carcass.
    pub poisson: f64,
    /// Inflation (gauge) pressure, Pa.
    pub pressure: f64,
    /// Stiffness-proportional (Rayleigh) damping `beta`, s.
    pub damping: f64,
    /// Friction coefficient of the tread against the terrain.
    pub friction: f64,
    /// Elements around the axle.
    pub n_around: usize,
    /// Elements across the section.
    pub n_across: usize,
    /// How the beads hold to the rim.
    #[serde(default)]
    pub bead: BeadMount,
}

impl AncfTireData {
    /// The HMMWV's 37x12.5R16.5-class tire (module docs give each value's source).
    pub fn hmmwv() -> Self {
        Self {
            radius: 0.4673,
            rim_radius: 0.2683,
            rim_width: 0.254,
            thickness: 0.015,
            mass: 37.6,
            young: 1.0e8,
            poisson: 0.3,
            pressure: 2.0e5,
            damping: 0.0,
            friction: 0.9,
            n_around: 24,
            n_across: 6,
            bead: BeadMount::Hinged,
        }
    }

    /// Check the fields; errors name them (`ancf_tire.radius` ...), including a carcass that
    /// does not fit its rim.
    pub fn validate(&self) -> Result<()> {
        check_positive("ancf_tire.radius", self.radius)?;
        check_positive("ancf_tire.rim_radius", self.rim_radius)?;
        check_positive("ancf_tire.rim_width", self.rim_width)?;
        check_positive("ancf_tire.thickness", self.thickness)?;
        check_positive("ancf_tire.mass", self.mass)?;
        check_positive("ancf_tire.young", self.young)?;
        check_positive("ancf_tire.pressure", self.pressure)?;
        check_non_negative("ancf_tire.damping", self.damping)?;
        check_non_negative("ancf_tire.friction", self.friction)?;
        if !(self.poisson.is_finite() && self.poisson > -1.0 && self.poisson < 0.5) {
            return Err(VehicleError::invalid(
                "ancf_tire.poisson",
                self.poisson,
                "must lie in (-1, 0.5)",
            ));
        }
        if self.n_around < 3 {
            return Err(VehicleError::invalid(
                "ancf_tire.n_around",
                self.n_around,
                "needs at least 3 elements around",
            ));
        }
        if self.n_across < 1 {
            return Err(VehicleError::invalid(
                "ancf_tire.n_across",
                self.n_across,
                "needs at least 1 element across",
            ));
        }
        self.geometry(Vector3::zeros()).map(|_| ())
    }

    /// The carcass geometry (module docs) centred at `centre`, axle along `Y`. Errors: a rim
    /// at or above the tread's mid surface (`ancf_tire.rim_radius`), a section too large
    /// for its ring (`ancf_tire.rim_width`).
    pub fn geometry(&self, centre: Vector3<f64>) -> Result<TireGeometry> {
        let r_mid = self.radius - 0.5 * self.thickness;
        let depth = r_mid - self.rim_radius;
        if depth <= 0.0 || !depth.is_finite() {
            return Err(VehicleError::invalid(
                "ancf_tire.rim_radius",
                self.rim_radius,
                format!(
                    "the rim must lie inside the tread's mid surface (radius {r_mid} m): the tire does not fit the rim"
                ),
            ));
        }
        let half_width = 0.5 * self.rim_width;
        let bead_angle = 2.0 * (depth / half_width).atan();
        let section_radius = half_width / bead_angle.sin();
        let ring_radius = r_mid - section_radius;
        if section_radius >= ring_radius || !section_radius.is_finite() {
            return Err(VehicleError::invalid(
                "ancf_tire.rim_width",
                self.rim_width,
                format!(
                    "gives a section radius {section_radius} m not below the ring radius {ring_radius} m: the tire does not fit the rim"
                ),
            ));
        }
        Ok(TireGeometry {
            centre,
            ring_radius,
            section_radius,
            bead_angle,
            n_around: self.n_around,
            n_across: self.n_across,
            thickness: self.thickness,
        })
    }

    /// Build the carcass at the origin (axle `Y`) and inflate it with its beads held.
    pub fn inflate(&self) -> Result<AncfTireModel> {
        self.validate()?;
        let geometry = self.geometry(Vector3::zeros())?;
        let unit = TireMesh::new(
            geometry,
            ShellMaterial::isotropic(self.young, self.poisson, 1.0)?,
        )?;
        let density = self.mass / unit.mesh.total_mass();
        let tire = TireMesh::new(
            geometry,
            ShellMaterial::isotropic(self.young, self.poisson, density)?,
        )?;
        let inflated = InflatedTire::new(&tire, self.pressure, self.bead, 4)?;
        Ok(AncfTireModel {
            data: self.clone(),
            tire,
            inflated,
        })
    }

    /// The tread's contact material.
    pub fn material(&self) -> ContactMaterial {
        ContactMaterial::with_friction(self.friction)
    }
}

/// An inflated ANCF tire ready to be mounted on wheels (one inflation serves every wheel).
#[derive(Debug, Clone)]
pub struct AncfTireModel {
    data: AncfTireData,
    tire: TireMesh,
    inflated: InflatedTire,
}

impl AncfTireModel {
    /// The description it was built from.
    pub fn data(&self) -> &AncfTireData {
        &self.data
    }

    /// The carcass as meshed (its geometry, bead rings and reference mesh).
    pub fn tire(&self) -> &TireMesh {
        &self.tire
    }

    /// The inflated carcass at the origin.
    pub fn inflated(&self) -> &InflatedTire {
        &self.inflated
    }

    /// The inflated tire's free radius: the largest distance of the tread's outer face
    /// from the axle, m.
    pub fn inflated_radius(&self) -> f64 {
        let half_t = 0.5 * self.data.thickness;
        self.inflated
            .inflated
            .nodes()
            .iter()
            .map(|n| n.position.x.hypot(n.position.z) + half_t)
            .fold(0.0, f64::max)
    }

    /// Mount a copy of the inflated tire on the spindle body `spindle` of `sys` (its axle
    /// the body's local `Y` axis through its centre of mass, at its current pose) and add
    /// it to `sys` as an item named `name`: every bead node tied to the spindle as the
    /// data's `bead` says, its element faces (triangles swept by `t / 2`,
    /// [`ShellItem::set_contact_faces`]) against the body colliders: a grain smaller than an
    /// element cannot pass between the nodes.
    pub fn mount(&self, sys: &mut System, name: &str, spindle: BodyHandle) -> Result<ItemHandle> {
        let pose: Isometry3<f64> = sys.body(spindle)?.pose();
        let mut item = ShellItem::new(name, self.inflated.placed(&pose)?)?;
        item.set_damping(self.data.damping)?;
        item.set_contact_faces(0.5 * self.data.thickness, self.data.material())?;
        mount_on_rim_at(&mut item, &self.tire.beads, spindle, &pose, self.data.bead)?;
        Ok(sys.add_item(Box::new(item)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_geometry_reproduces_the_size() {
        let d = AncfTireData::hmmwv();
        let g = d.geometry(Vector3::zeros()).unwrap();
        let half_t = 0.5 * d.thickness;
        assert!((g.ring_radius + g.section_radius + half_t - d.radius).abs() < 1e-12);
        assert!((g.bead_radius() - d.rim_radius).abs() < 1e-12);
        let width = 2.0 * g.section_radius * g.bead_angle.sin();
        assert!((width - d.rim_width).abs() < 1e-12);
        assert!(g.bead_angle > 0.5 * std::f64::consts::PI);
    }

    /// The section width is the carcass' widest axial extent: the undeformed mesh's
    /// outer surface spans it.
    #[test]
    fn the_section_width_is_the_meshs_axial_extent() {
        let d = AncfTireData::hmmwv();
        let w = crate::tire::Tire::Ancf(d.clone()).section_width();
        let g = d.geometry(Vector3::zeros()).unwrap();
        // Sample the section circle from bead to bead: its widest point, plus the shell.
        let widest = (0..=1000)
            .map(|k| {
                let a = -g.bead_angle + 2.0 * g.bead_angle * k as f64 / 1000.0;
                2.0 * g.section_radius * a.sin().abs()
            })
            .fold(0.0, f64::max);
        assert!((w - (widest + d.thickness)).abs() < 1e-6, "{w} vs {widest}");
        assert!(w > d.rim_width, "the carcass bulges past its rim: {w}");
    }

    #[test]
    fn the_inflated_tire_has_the_mass_and_about_the_size() {
        let mut d = AncfTireData::hmmwv();
        d.n_around = 16;
        d.n_across = 4;
        let m = d.inflate().unwrap();
        let mesh_mass = m.inflated().mesh.total_mass();
        assert!((mesh_mass - d.mass).abs() < 1e-9 * d.mass, "{mesh_mass}");
        let r = m.inflated_radius();
        // Inflation stretches the carcass by a little, never shrinks it.
        assert!(r > d.radius - 1e-6 && r < 1.05 * d.radius, "{r}");
    }

    #[test]
    fn bad_input_names_the_field() {
        type Edit = fn(&mut AncfTireData);
        let cases: [(&str, Edit); 6] = [
            ("ancf_tire.pressure", |d| d.pressure = 0.0),
            ("ancf_tire.pressure", |d| d.pressure = -1e5),
            ("ancf_tire.rim_radius", |d| d.rim_radius = 0.47),
            ("ancf_tire.rim_width", |d| d.rim_width = 2.0),
            ("ancf_tire.thickness", |d| d.thickness = f64::NAN),
            ("ancf_tire.poisson", |d| d.poisson = 0.5),
        ];
        for (field, edit) in cases {
            let mut d = AncfTireData::hmmwv();
            edit(&mut d);
            let e = d.validate().unwrap_err().to_string();
            assert!(e.contains(field), "{field}: {e}");
            assert!(d.inflate().is_err());
        }
    }
}
