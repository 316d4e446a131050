//! Contact materials.
//!
//! One material serves both contact methods: NSC (complementarity) uses `friction`,
//! `rolling_friction`, `spinning_friction` and `compliance`; SMC (penalty) uses the elastic
//! constants (`young_modulus`, `poisson_ratio`), `restitution`, `friction` and
//! `rolling_friction`. When two materials meet, [`ContactMaterial::combine`] mixes them as
//! Project Chrono does: friction coefficients and restitution take the minimum, compliances
//! add (springs in series). The SMC code needs the two sides' elastic constants separately:
//! [`effective_young_modulus`] and [`effective_shear_modulus`] (Hertz and Mindlin's
//! composite moduli).

use serde::{Deserialize, Serialize};

use crate::error::{ChronoError, Result, check_non_negative, check_positive};

/// Surface properties of a collider.
///
/// Fields missing from a serialized material take their [`Default`] values.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct ContactMaterial {
    /// Coulomb friction coefficient `mu` (dimensionless, >= 0).
    pub friction: f64,
    /// Coefficient of restitution `e` in [0, 1] (SMC; NSC contacts are plastic).
    pub restitution: f64,
    /// Normal compliance (m/N) of an NSC contact, 0 = rigid. Adds `eps = c/h^2` to the
    /// diagonal of `N` (Chrono's cfm).
    pub compliance: f64,
    /// Young's modulus (Pa) for SMC Hertz contact.
    pub young_modulus: f64,
    /// Poisson ratio for SMC Hertz contact, in [0, 0.5).
    pub poisson_ratio: f64,
    /// Rolling friction coefficient `mu_r` (dimensionless, >= 0): the rolling resistance
    /// torque is at most `mu_r R F_n` with `R` the effective radius of the contact and
    /// `F_n` the normal force (Ai et al., "Assessment of rolling resistance models in
    /// discrete element simulations", Powder Technol. 206, 2011, model A). NSC rolling
    /// cones bound the torque impulse by `mu_r R g_n`. 0 = no rolling resistance.
    pub rolling_friction: f64,
    /// Spinning (twisting) friction coefficient `mu_s` (dimensionless, >= 0): the torque
    /// about the contact normal is at most `mu_s R F_n`. 0 = none.
    pub spinning_friction: f64,
}

impl Default for ContactMaterial {
    fn default() -> Self {
        Self {
            friction: 0.6,
            restitution: 0.0,
            compliance: 0.0,
            young_modulus: 2e7,
            poisson_ratio: 0.3,
            rolling_friction: 0.0,
            spinning_friction: 0.0,
        }
    }
}

impl ContactMaterial {
    /// A rigid NSC material with friction coefficient `mu`.
    pub fn with_friction(mu: f64) -> Self {
        Self {
            friction: mu,
            ..Self::default()
        }
    }

    /// A material for SMC (penalty) contact: Young's modulus `young` (Pa), Poisson ratio
    /// `poisson`, restitution `restitution` and friction `mu` (check with
    /// [`validate`](Self::validate)).
    pub fn smc(young: f64, poisson: f64, restitution: f64, mu: f64) -> Self {
        Self {
            friction: mu,
            restitution,
            young_modulus: young,
            poisson_ratio: poisson,
            ..Self::default()
        }
    }

    /// The same material with rolling friction coefficient `mu_r` (dimensionless).
    pub fn with_rolling_friction(mut self, mu_r: f64) -> Self {
        self.rolling_friction = mu_r;
        self
    }

    /// The same material with spinning friction coefficient `mu_s` (dimensionless).
    pub fn with_spinning_friction(mut self, mu_s: f64) -> Self {
        self.spinning_friction = mu_s;
        self
    }

    /// Check every field; the error names the field and the value.
    pub fn validate(&self) -> Result<()> {
        check_non_negative("material.friction", self.friction)?;
        check_non_negative("material.rolling_friction", self.rolling_friction)?;
        check_non_negative("material.spinning_friction", self.spinning_friction)?;
        check_non_negative("material.compliance", self.compliance)?;
        check_positive("material.young_modulus", self.young_modulus)?;
        if !(self.restitution.is_finite() && (0.0..=1.0).contains(&self.restitution)) {
            return Err(ChronoError::invalid(
                "material.restitution",
                self.restitution,
                "must be in [0, 1]",
            ));
        }
        if !(self.poisson_ratio.is_finite() && (0.0..0.5).contains(&self.poisson_ratio)) {
            return Err(ChronoError::invalid(
                "material.poisson_ratio",
                self.poisson_ratio,
                "must be in [0, 0.5)",
            ));
        }
        Ok(())
    }

    /// The material of a contact between `self` and `other`: min friction and restitution,
    /// summed compliance, effective Hertz modulus terms kept per side by the SMC code.
    pub fn combine(&self, other: &ContactMaterial) -> ContactMaterial {
        ContactMaterial {
            friction: self.friction.min(other.friction),
            restitution: self.restitution.min(other.restitution),
            compliance: self.compliance + other.compliance,
            young_modulus: self.young_modulus.min(other.young_modulus),
            poisson_ratio: self.poisson_ratio.max(other.poisson_ratio),
            rolling_friction: self.rolling_friction.min(other.rolling_friction),
            spinning_friction: self.spinning_friction.min(other.spinning_friction),
        }
    }
}

/// Friction coefficients that one body imposes on all its contacts with other bodies,
/// in place of [`ContactMaterial::combine`]'s minimum (set with
/// [`System::set_contact_friction`](crate::System::set_contact_friction)).
///
/// The minimum rule cannot make a wall rougher than the grains it touches: DEM studies
/// give grain–wall friction its own value, e.g. Y. C. Zhou, B. H. Xu, A. B. Yu and
/// P. Zulli, "An experimental and numerical study of the angle of repose of coarse
/// spheres", Powder Technol. 125 (2002) 45–54, whose base case has `mu_pw = 0.6` against
/// `mu_pp = 0.4`. Elastic constants and restitution are still taken from both sides.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ContactFriction {
    /// Coulomb friction coefficient `mu` (dimensionless, >= 0).
    pub friction: f64,
    /// Rolling friction coefficient `mu_r` (dimensionless, >= 0; torque `mu_r R F_n`).
    pub rolling_friction: f64,
    /// Spinning friction coefficient `mu_s` (dimensionless, >= 0; torque `mu_s R F_n`).
    pub spinning_friction: f64,
}

impl ContactFriction {
    /// The friction coefficients of `material`.
    pub fn of(material: &ContactMaterial) -> Self {
        Self {
            friction: material.friction,
            rolling_friction: material.rolling_friction,
            spinning_friction: material.spinning_friction,
        }
    }

    /// Check every field; the error names the field and the value.
    pub fn validate(&self) -> Result<()> {
        check_non_negative("contact_friction.friction", self.friction)?;
        check_non_negative("contact_friction.rolling_friction", self.rolling_friction)?;
        check_non_negative("contact_friction.spinning_friction", self.spinning_friction)?;
        Ok(())
    }

    /// The coefficient-wise minimum of two (a contact between two bodies that both carry
    /// one).
    pub fn min(&self, other: &ContactFriction) -> ContactFriction {
        ContactFriction {
            friction: self.friction.min(other.friction),
            rolling_friction: self.rolling_friction.min(other.rolling_friction),
            spinning_friction: self.spinning_friction.min(other.spinning_friction),
        }
    }

    /// Write the coefficients into a contact's combined material.
    pub fn apply(&self, material: &mut ContactMaterial) {
        material.friction = self.friction;
        material.rolling_friction = self.rolling_friction;
        material.spinning_friction = self.spinning_friction;
    }
}

/// Hertz's effective Young's modulus of two elastic bodies (Pa):
/// `1/E* = (1 - nu_a^2)/E_a + (1 - nu_b^2)/E_b` (K. L. Johnson, *Contact Mechanics*,
/// Cambridge 1985, eq. 4.22).
pub fn effective_young_modulus(a: &ContactMaterial, b: &ContactMaterial) -> f64 {
    let side = |m: &ContactMaterial| (1.0 - m.poisson_ratio * m.poisson_ratio) / m.young_modulus;
    1.0 / (side(a) + side(b))
}

/// Mindlin's effective shear modulus of two elastic bodies (Pa):
/// `1/G* = (2 - nu_a)/G_a + (2 - nu_b)/G_b` with `G = E / (2 (1 + nu))`, i.e.
/// `1/G* = 2 (2 - nu_a)(1 + nu_a)/E_a + 2 (2 - nu_b)(1 + nu_b)/E_b` (Johnson 1985, §7.2;
/// the tangential stiffness of a Hertz contact is `k_t = 8 G* a`, `a = sqrt(R delta)`).
pub fn effective_shear_modulus(a: &ContactMaterial, b: &ContactMaterial) -> f64 {
    let side = |m: &ContactMaterial| {
        2.0 * (2.0 - m.poisson_ratio) * (1.0 + m.poisson_ratio) / m.young_modulus
    };
    1.0 / (side(a) + side(b))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rejects_negative_friction() {
        let m = ContactMaterial::with_friction(-0.1);
        let e = m.validate().unwrap_err().to_string();
        assert!(e.contains("material.friction") && e.contains("-0.1"), "{e}");
    }

    #[test]
    fn combine_takes_min_friction_and_sums_compliance() {
        let a = ContactMaterial {
            friction: 0.3,
            compliance: 1e-6,
            ..Default::default()
        };
        let b = ContactMaterial {
            friction: 0.5,
            compliance: 2e-6,
            ..Default::default()
        };
        let c = a.combine(&b);
        assert_eq!(c.friction, 0.3);
        assert!((c.compliance - 3e-6).abs() < 1e-18);
    }

    #[test]
    fn rejects_negative_rolling_friction_and_reads_old_json() {
        let m = ContactMaterial::with_friction(0.3).with_rolling_friction(-0.2);
        let e = m.validate().unwrap_err().to_string();
        assert!(
            e.contains("material.rolling_friction") && e.contains("-0.2"),
            "{e}"
        );
        let m: ContactMaterial = serde_json::from_str(r#"{"friction": 0.4}"#).unwrap();
        assert_eq!(m.friction, 0.4);
        assert_eq!(m.rolling_friction, 0.0);
    }

    #[test]
    fn contact_friction_checks_its_fields_and_takes_the_minimum() {
        let f = ContactFriction {
            friction: 0.6,
            rolling_friction: -0.01,
            spinning_friction: 0.0,
        };
        let e = f.validate().unwrap_err().to_string();
        assert!(
            e.contains("contact_friction.rolling_friction") && e.contains("-0.01"),
            "{e}"
        );
        let a =
            ContactFriction::of(&ContactMaterial::with_friction(0.6).with_rolling_friction(0.02));
        let b =
            ContactFriction::of(&ContactMaterial::with_friction(0.4).with_rolling_friction(0.05));
        let m = a.min(&b);
        assert_eq!((m.friction, m.rolling_friction), (0.4, 0.02));
        let mut mat = ContactMaterial::with_friction(0.1);
        a.apply(&mut mat);
        assert_eq!((mat.friction, mat.rolling_friction), (0.6, 0.02));
    }

    #[test]
    fn effective_moduli_of_equal_materials() {
        let m = ContactMaterial::smc(1e7, 0.3, 0.5, 0.5);
        let e = effective_young_modulus(&m, &m);
        assert!((e - 1e7 / (2.0 * (1.0 - 0.09))).abs() < 1e-6);
        let g = effective_shear_modulus(&m, &m);
        let g1 = 1e7 / 2.6;
        assert!((g - g1 / (2.0 * 1.7)).abs() < 1e-6);
    }
}
