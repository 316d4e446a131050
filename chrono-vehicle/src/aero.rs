//! Aerodynamic drag on the chassis: the force that, with the tires' rolling resistance,
//! sets a vehicle's top speed when its engine does not.
//!
//! ```text
//! F = -1/2 rho_air C_d A |v| v        N, at the chassis center of mass
//! ```
//!
//! `v` the chassis' center-of-mass velocity relative to still air (m/s), `C_d` the drag
//! coefficient, `A` the frontal area (m^2), `rho_air` the air density (kg/m^3). The force
//! acts at the center of mass (no pitching moment from the center of pressure: at the
//! speeds of a tactical truck the lift and pitch terms are small against the tire loads,
//! and their coefficients are not published for the HMMWV), and it is explicit: evaluated
//! from the velocity at the start of each step, which is stable for any step a vehicle
//! takes (`h << m / (rho C_d A |v|)`, about 20 s at 30 m/s for the HMMWV).
//! Reference: the standard quadratic drag law (e.g. T. D. Gillespie, *Fundamentals of
//! Vehicle Dynamics*, SAE 1992, ch. 4).

use chrono_core::BodyHandle;
use chrono_core::force::{BodyLoads, ForceElement, check_body};
use chrono_core::item::StepContext;
use chrono_core::math::Vector3;
use serde::{Deserialize, Serialize};

use crate::error::{Result, VehicleError};

/// Drag parameters of a chassis (JSON: `{"drag_coefficient": 0.6, "frontal_area": 3.4,
/// "air_density": 1.2}`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AeroDragData {
    /// Drag coefficient `C_d` (finite, >= 0).
    pub drag_coefficient: f64,
    /// Frontal area `A`, m^2 (finite, >= 0).
    pub frontal_area: f64,
    /// Air density, kg/m^3 (finite, > 0; 1.2 at 20 degC at sea level).
    pub air_density: f64,
}

impl AeroDragData {
    /// Check every field; errors name `{prefix}.field`.
    pub fn validate(&self, prefix: &str) -> Result<()> {
        let check = |name: &str, v: f64, positive: bool| {
            let bad = !v.is_finite() || v < 0.0 || (positive && v == 0.0);
            if bad {
                Err(VehicleError::invalid(
                    format!("{prefix}.{name}"),
                    v,
                    if positive {
                        "must be finite and > 0"
                    } else {
                        "must be finite and >= 0"
                    },
                ))
            } else {
                Ok(())
            }
        };
        check("drag_coefficient", self.drag_coefficient, false)?;
        check("frontal_area", self.frontal_area, false)?;
        check("air_density", self.air_density, true)
    }

    /// The factor `k = 1/2 rho C_d A` of `F = -k |v| v`, kg/m.
    pub fn factor(&self) -> f64 {
        0.5 * self.air_density * self.drag_coefficient * self.frontal_area
    }
}

/// The drag force element on one body (the chassis).
#[derive(Debug, Clone)]
pub struct AeroDrag {
    name: String,
    body: BodyHandle,
    k: f64,
    force: Vector3<f64>,
}

impl AeroDrag {
    /// Drag on `body` with `data` (validated; errors name `chassis.aero.<field>`).
    pub fn new(name: impl Into<String>, body: BodyHandle, data: &AeroDragData) -> Result<Self> {
        data.validate("chassis.aero")?;
        Ok(Self {
            name: name.into(),
            body,
            k: data.factor(),
            force: Vector3::zeros(),
        })
    }

    /// The force of the last evaluation, N (world).
    pub fn force(&self) -> Vector3<f64> {
        self.force
    }
}

impl ForceElement for AeroDrag {
    fn name(&self) -> &str {
        &self.name
    }

    fn body_handles(&self) -> Vec<BodyHandle> {
        vec![self.body]
    }

    fn attach(&mut self, bodies: &chrono_core::Bodies) -> chrono_core::Result<()> {
        check_body(
            &format!("aero drag \"{}\".body", self.name),
            self.body,
            bodies,
        )
    }

    fn evaluate(
        &mut self,
        _ctx: &StepContext,
        bodies: &chrono_core::Bodies,
        loads: &mut BodyLoads,
    ) -> chrono_core::Result<()> {
        let b = &bodies[self.body];
        let v = b.linear_velocity();
        self.force = -self.k * v.norm() * v;
        loads.add_force_at(self.body, &self.force, &b.position());
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use chrono_ccp::{Apgd, SolverSettings};
    use chrono_core::{RigidBodyBuilder, System, SystemSettings};

    /// A body coasting against quadratic drag alone: `dv/dt = -(k/m) v^2`, so
    /// `v(t) = v0 / (1 + (k/m) v0 t)`. The explicit force is first order in `h`: at
    /// `h = 1e-3` s the speed after 10 s must match to 1e-4 (relative).
    #[test]
    fn coasting_body_follows_the_quadratic_drag_law() {
        let settings = SystemSettings {
            gravity: Vector3::zeros(),
            ..SystemSettings::default()
        };
        let solver = Box::new(Apgd::new(SolverSettings::default()));
        let mut sys = System::new(settings, solver).unwrap();
        let (m, v0) = (100.0, 30.0);
        let body = sys
            .add_body(
                RigidBodyBuilder::dynamic()
                    .mass(m)
                    .inertia_diagonal(Vector3::new(1.0, 1.0, 1.0))
                    .linear_velocity(Vector3::new(v0, 0.0, 0.0)),
            )
            .unwrap();
        let data = AeroDragData {
            drag_coefficient: 0.5,
            frontal_area: 2.0,
            air_density: 1.2,
        };
        sys.add_force_element(Box::new(AeroDrag::new("drag", body, &data).unwrap()))
            .unwrap();
        let h = 1e-3;
        for _ in 0..10_000 {
            sys.step(h).unwrap();
        }
        let exact = v0 / (1.0 + data.factor() / m * v0 * 10.0);
        let v = sys.body(body).unwrap().linear_velocity();
        assert!((v.x / exact - 1.0).abs() < 1e-4, "{} vs {exact}", v.x);
        assert!(v.y.abs() < 1e-12 && v.z.abs() < 1e-12);
    }

    #[test]
    fn bad_parameters_are_named() {
        let bad = AeroDragData {
            drag_coefficient: 0.6,
            frontal_area: -1.0,
            air_density: 1.2,
        };
        let e = bad.validate("chassis.aero").unwrap_err().to_string();
        assert!(
            e.contains("chassis.aero.frontal_area") && e.contains("-1"),
            "{e}"
        );
        let bad = AeroDragData {
            air_density: 0.0,
            ..bad
        };
        assert!(bad.validate("x").is_err());
    }
}
