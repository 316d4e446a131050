//! Stokes flow through a square array of fixed cylinders: one cell (pitch `P` in x and z)
//! of WCSPH fluid around a rigid cylinder along y with BCE markers, a slab periodic in y
//! (quasi-2D), periodic in x and z, driven along x by a uniform body force `f` on the
//! fluid. No gravity.
//!
//! The reference is Sangani & Acrivos (1982, "Slow flow past periodic arrays of cylinders
//! with application to heat transfer", Int. J. Multiphase Flow 8:193-206, Table 1), whose
//! drag is defined for flow driven by a mean pressure gradient `G`: the force per length on
//! one cylinder is `F = G P^2` (the gradient acts on the whole cell, the cylinder's
//! volume included) and `K = F / (mu U)` with `U` the superficial velocity (the volume
//! flux over the whole cell's cross-section). A body force `f` on the fluid drives the same
//! velocity field as `G = rho f` (the momentum equations in the fluid are the same), but the
//! cylinder then feels `F_b = rho f (1 - c) P^2` (no pressure gradient acts on its volume), so
//!
//! ```text
//! K = rho f P^2 / (mu U) = F_b / ((1 - c) mu U),     c = pi D^2 / (4 P^2)
//! ```
//!
//! ([`drag_coefficient`]). The cell is rounded to whole spacings, and `c` is that of the
//! rounded cell.
//!
//! ```
//! use chrono_fsi::cylinder_array::{CylinderArrayParams, cylinder_array};
//!
//! let p = CylinderArrayParams { spacing: 0.004, ..CylinderArrayParams::default() };
//! let solver = chrono_ccp::Psor::new(Default::default());
//! let mut scene = cylinder_array(&p, Box::new(solver)).unwrap();
//! scene.system.step(2e-3).unwrap();
//! // the flow starts along x
//! assert!(scene.superficial_velocity() > 0.0);
//! ```

use std::f64::consts::PI;

use chrono_core::descriptor::CcpSolver;
use chrono_core::item::ItemHandle;
use chrono_core::math::{Isometry3, Vector3};
use chrono_core::particles::lattice::slab_layers;
use chrono_core::{BodyHandle, RigidBodyBuilder, Shape, System};
use chrono_sph::{ShiftForm, Shifting, SphSettings};

use crate::error::{FsiError, Result, check_positive};
use crate::periodic::DrivenCell;
use crate::{FsiBuilder, SphFluid};

/// Sangani & Acrivos (1982), Table 1, square arrays: solid fraction `c` and
/// `K = F / (mu U)` (pressure-driven force per length over the viscosity and the
/// superficial velocity; see the [module docs](self)).
pub const SANGANI_ACRIVOS_SQUARE: [(f64, f64); 9] = [
    (0.05, 15.56),
    (0.10, 24.83),
    (0.20, 51.53),
    (0.30, 102.90),
    (0.40, 217.89),
    (0.50, 532.55),
    (0.60, 1.763e3),
    (0.70, 1.352e4),
    (0.75, 1.263e5),
];

/// Sangani & Acrivos' dilute expansion for the square array (extending Hasimoto 1959),
/// `K = 4 pi / (-ln(c)/2 - 0.738 + c - 0.887 c^2 + 2.038 c^3)`: within 0.2 % of their
/// Table 1 at `c` = 0.05 and 0.1.
pub fn sangani_acrivos_dilute(c: f64) -> f64 {
    4.0 * PI / (-0.5 * c.ln() - 0.738 + c - 0.887 * c * c + 2.038 * c.powi(3))
}

/// `K(c)` of Sangani & Acrivos' Table 1 at solid fraction `c` in `[0.05, 0.75]`,
/// interpolated linearly in `(c, ln K)` between the table's rows (`K` grows roughly
/// exponentially with `c`); below the table, in `(0, 0.05)`, their dilute expansion
/// ([`sangani_acrivos_dilute`]; a cell rounded to whole spacings can land just below
/// 0.05); `None` above the table or for a `c` that is not positive.
pub fn sangani_acrivos_square(c: f64) -> Option<f64> {
    crate::periodic::drag_factor_from_table(&SANGANI_ACRIVOS_SQUARE, c, sangani_acrivos_dilute)
}

/// `K = rho f P^2 / (mu U)` from the cylinder's drag per length `F_b` (N/m) in the
/// body-force-driven cell: `F_b / ((1 - c) mu U)` (see the [module docs](self)).
pub fn drag_coefficient(drag_per_length: f64, solid_fraction: f64, mu: f64, u: f64) -> f64 {
    drag_per_length / ((1.0 - solid_fraction) * mu * u)
}

/// Parameters of [`cylinder_array`] (SI units).
#[derive(Debug, Clone, PartialEq)]
pub struct CylinderArrayParams {
    /// Cylinder diameter `D`, m.
    pub diameter: f64,
    /// Solid fraction `c = pi D^2 / (4 P^2)` (sets the pitch `P`), in `(0, pi/4)`.
    pub solid_fraction: f64,
    /// Fluid density, kg/m^3.
    pub rho: f64,
    /// Dynamic viscosity, Pa s.
    pub viscosity: f64,
    /// Driving body force on the fluid along x, m/s^2.
    pub body_force: f64,
    /// Particle spacing, m.
    pub spacing: f64,
    /// Smoothing length over spacing `h / dp`.
    pub h_over_dp: f64,
    /// Particle shifting coefficient `A` ([`chrono_sph::Shifting`], `>= 0`; 0: none).
    /// Default 4 with [`ShiftForm::DeltaPlus`] (Sun et al. 2017's published form): without
    /// shifting the particle order decays in a long run and the array's resistance creeps
    /// up (docs/validation-fsi.md, "The drift is lost particle order").
    pub shifting: f64,
    /// The shifting's form ([`ShiftForm`]; used when `shifting > 0`).
    pub shift_form: ShiftForm,
}

impl Default for CylinderArrayParams {
    /// `D = 0.02 m`, `c = 0.1`, water's density, `mu = 1 Pa s`, `f = 0.05 m/s^2`
    /// (Reynolds number `rho U D / mu ~ 0.3`), `dp = D / 8`, `h = 1.3 dp`.
    fn default() -> Self {
        Self {
            diameter: 0.02,
            solid_fraction: 0.1,
            rho: 1000.0,
            viscosity: 1.0,
            body_force: 0.05,
            spacing: 0.0025,
            h_over_dp: SphSettings::default().h_over_dp,
            shifting: Shifting::delta_plus().coefficient,
            shift_form: ShiftForm::DeltaPlus,
        }
    }
}

impl CylinderArrayParams {
    /// The pitch `P = D sqrt(pi / (4 c))` before rounding to whole spacings, m.
    pub fn pitch(&self) -> f64 {
        self.diameter * (PI / (4.0 * self.solid_fraction)).sqrt()
    }

    /// Checks every field; the error names it.
    pub fn validate(&self) -> Result<()> {
        for (f, v) in [
            ("diameter", self.diameter),
            ("rho", self.rho),
            ("viscosity", self.viscosity),
            ("spacing", self.spacing),
            ("h_over_dp", self.h_over_dp),
        ] {
            check_positive(f, v)?;
        }
        if !(self.shifting.is_finite() && self.shifting >= 0.0) {
            return Err(FsiError::invalid(
                "shifting",
                self.shifting,
                "must be finite and >= 0",
            ));
        }
        let c = self.solid_fraction;
        if !(c.is_finite() && c > 0.0 && c < 0.75) {
            return Err(FsiError::invalid(
                "solid_fraction",
                c,
                "must be in (0, 0.75) (touching cylinders at pi/4)",
            ));
        }
        if !(self.body_force.is_finite() && self.body_force != 0.0) {
            return Err(FsiError::invalid(
                "body_force",
                self.body_force,
                "must be finite and non-zero",
            ));
        }
        let gap = self.pitch() - self.diameter;
        let support = 2.0 * self.h_over_dp * self.spacing;
        if gap < support {
            return Err(FsiError::invalid(
                "spacing",
                self.spacing,
                format!(
                    "the gap between cylinders ({gap:.4} m) must hold a kernel support ({support:.4} m)"
                ),
            ));
        }
        Ok(())
    }
}

/// The scene: the system with the fixed cylinder and the fluid item.
pub struct CylinderArray {
    /// The multibody system.
    pub system: System,
    /// The fluid item.
    pub fluid: ItemHandle,
    /// The fixed cylinder.
    pub cylinder: BodyHandle,
    /// The cell actually used (x, y, z), m: pitch, slab thickness, pitch.
    pub cell: [f64; 3],
    /// The solid fraction of the rounded cell.
    pub solid_fraction: f64,
    /// The fluid's rest density, kg/m^3.
    pub rho0: f64,
}

impl CylinderArray {
    /// The fluid item.
    pub fn fluid(&self) -> &SphFluid {
        self.system
            .item::<SphFluid>(self.fluid)
            .expect("the scene's fluid item")
    }

    /// The fluid's drag on the cylinder per length along its axis, x component (N/m),
    /// over the last step.
    pub fn drag_per_length(&self) -> f64 {
        self.fluid()
            .body_load(self.cylinder)
            .map_or(0.0, |l| l[0].x / self.cell[1])
    }

    /// The superficial velocity along x (m/s): the fluid's volume flux over the whole
    /// cell, its momentum over `rho_0` and the cell volume, `sum_i m_i u_i / (rho_0 P^2 L_y)`.
    pub fn superficial_velocity(&self) -> f64 {
        let sph = self.fluid().sph();
        let d = sph.data();
        let mom: f64 = (0..d.len())
            .filter(|&k| d.kind[k] == chrono_sph::data::FLUID)
            .map(|k| d.mass[k] * d.vx[k])
            .sum();
        mom / (self.rho0 * self.cell[0] * self.cell[1] * self.cell[2])
    }
}

/// Builds the scene of `p` (see the [module docs](self)) with the multibody `solver`.
/// Errors name the parameter (see [`CylinderArrayParams::validate`]) or the body (a
/// cylinder not resolved by the spacing, [`FsiBuilder::add_body`]).
pub fn cylinder_array(
    p: &CylinderArrayParams,
    solver: Box<dyn CcpSolver>,
) -> Result<CylinderArray> {
    p.validate()?;
    let dp = p.spacing;
    let px = ((p.pitch() / dp).round().max(1.0)) * dp;
    let ly = slab_layers(p.h_over_dp) as f64 * dp;
    let cell = [px, ly, px];
    let c = PI * p.diameter * p.diameter / (4.0 * px * px);
    // the expected superficial speed from the table (or the dilute limit above it); the
    // fluid's mean speed is higher by 1 / (1 - c)
    let k = sangani_acrivos_square(c).unwrap_or(4.0 * PI / (-0.5 * c.ln() - 0.738).max(0.1));
    let u = p.rho * p.body_force.abs() * px * px / (p.viscosity * k);
    let (settings, mut system) = DrivenCell {
        cell,
        spacing: dp,
        h_over_dp: p.h_over_dp,
        rho: p.rho,
        viscosity: p.viscosity,
        body_force: p.body_force,
        v_max: 2.0 * u / (1.0 - c),
        diameter: p.diameter,
        shifting: (p.shifting > 0.0).then_some(Shifting {
            coefficient: p.shifting,
            form: p.shift_form,
        }),
    }
    .build(solver)?;
    let shape = Shape::Cylinder {
        half_length: 0.5 * ly,
        radius: 0.5 * p.diameter,
    };
    let cylinder = system.add_body(
        RigidBodyBuilder::fixed()
            .name("cylinder")
            .position(Vector3::new(0.5 * px, 0.5 * ly, 0.5 * px))
            .collider(shape, Isometry3::identity(), Default::default()),
    )?;
    let mut fsi = FsiBuilder::new(settings)?;
    fsi.add_fluid_box([0.0; 3], cell, None)?;
    fsi.add_body(&system, cylinder)?;
    let fluid = system.add_item(Box::new(fsi.build("fluid", 1)?));
    Ok(CylinderArray {
        system,
        fluid,
        cylinder,
        cell,
        solid_fraction: c,
        rho0: p.rho,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_table_is_interpolated_between_its_rows() {
        for (c, k) in SANGANI_ACRIVOS_SQUARE {
            let v = sangani_acrivos_square(c).unwrap();
            assert!((v / k - 1.0).abs() < 1e-12, "{c}: {v}");
        }
        let k = sangani_acrivos_square(0.15).unwrap();
        assert!(k > 24.83 && k < 51.53, "{k}");
        // geometric mean at the midpoint of a row pair
        assert!((k - (24.83f64 * 51.53).sqrt()).abs() < 1e-9, "{k}");
        assert_eq!(
            sangani_acrivos_square(0.01),
            Some(sangani_acrivos_dilute(0.01))
        );
        assert_eq!(sangani_acrivos_square(0.8), None);
        assert_eq!(sangani_acrivos_square(0.0), None);
        assert_eq!(sangani_acrivos_square(f64::NAN), None);
    }

    #[test]
    fn the_dilute_expansion_matches_the_table_where_it_applies() {
        // Sangani & Acrivos' own expansion reproduces their table at c = 0.05 and 0.1
        for c in [0.05, 0.1] {
            let k = sangani_acrivos_square(c).unwrap();
            assert!((sangani_acrivos_dilute(c) / k - 1.0).abs() < 2e-3, "{c}");
        }
    }

    #[test]
    fn the_body_force_drag_is_converted_to_the_pressure_driven_definition() {
        // force balance of the body-force cell: F_b = rho f (1 - c) P^2, so K = rho f P^2 / (mu U)
        let (rho, f, p, c, mu, u) = (1000.0, 0.05, 0.056, 0.1, 1.0, 0.006);
        let fb = rho * f * (1.0 - c) * p * p;
        let k = drag_coefficient(fb, c, mu, u);
        assert!((k - rho * f * p * p / (mu * u)).abs() < 1e-9 * k);
    }

    #[test]
    fn bad_parameters_are_named() {
        let base = CylinderArrayParams::default();
        for (field, p) in [
            (
                "diameter",
                CylinderArrayParams {
                    diameter: -1.0,
                    ..base.clone()
                },
            ),
            (
                "solid_fraction",
                CylinderArrayParams {
                    solid_fraction: 0.8,
                    ..base.clone()
                },
            ),
            (
                "body_force",
                CylinderArrayParams {
                    body_force: f64::NAN,
                    ..base.clone()
                },
            ),
            (
                "spacing",
                CylinderArrayParams {
                    spacing: 0.01,
                    solid_fraction: 0.5,
                    ..base.clone()
                },
            ),
            (
                "shifting",
                CylinderArrayParams {
                    shifting: -2.0,
                    ..base.clone()
                },
            ),
        ] {
            let e = p.validate().unwrap_err().to_string();
            assert!(e.contains(field), "{field}: {e}");
        }
    }
}
