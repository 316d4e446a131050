//! Contact materials.
//!
//! One material serves both contact methods: NSC (complementarity) uses `friction`,
//! `restitution` and `compliance`; SMC (penalty) uses the elastic constants. When two
//! materials meet, [`ContactMaterial::combine`] mixes them as Project Chrono does:
//! friction and restitution take the minimum, compliances add (springs in series).

use serde::{Deserialize, Serialize};

use crate::error::{ChronoError, Result, check_non_negative, check_positive};

/// Surface properties of a collider.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
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
}

impl Default for ContactMaterial {
    fn default() -> Self {
        Self {
            friction: 0.6,
            restitution: 0.0,
            compliance: 0.0,
            young_modulus: 2e7,
            poisson_ratio: 0.3,
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

    /// Check every field; the error names the field and the value.
    pub fn validate(&self) -> Result<()> {
        check_non_negative("material.friction", self.friction)?;
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
        }
    }
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
}
