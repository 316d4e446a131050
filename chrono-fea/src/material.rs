//! Material and cross-section of a beam or cable.

use crate::error::{Result, non_negative, positive};

/// Linear elastic material and cross-section of an ANCF cable/beam element.
///
/// The cable element (see [`AncfCable`](crate::element::AncfCable)) uses
/// - the axial stiffness `E A` (N) on the Green strain of the centre line,
/// - the bending stiffness `E I` (N m^2) on the curvature, the same in every bending
///   plane (the gradient-deficient element has no cross-section orientation, so `I` is
///   the second moment about the axis the load bends the section around),
/// - the mass per length `rho A` (kg/m) in the consistent mass matrix and gravity.
///
/// `damping` is the stiffness-proportional (Rayleigh beta) coefficient in seconds,
/// `f_d = damping * K v`: stored for the dynamic stepper; statics and the modal analysis
/// ignore it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BeamMaterial {
    /// Young's modulus `E`, Pa.
    pub young: f64,
    /// Density `rho`, kg/m^3.
    pub density: f64,
    /// Cross-section area `A`, m^2.
    pub area: f64,
    /// Second moment of area `I`, m^4.
    pub second_moment: f64,
    /// Stiffness-proportional damping coefficient, s (0: undamped).
    pub damping: f64,
}

impl BeamMaterial {
    /// A validated material: `young`, `density`, `area`, `second_moment` finite and > 0,
    /// `damping` finite and >= 0. The error names the field and value.
    pub fn new(
        young: f64,
        density: f64,
        area: f64,
        second_moment: f64,
        damping: f64,
    ) -> Result<Self> {
        Ok(Self {
            young: positive("material.young", young)?,
            density: positive("material.density", density)?,
            area: positive("material.area", area)?,
            second_moment: positive("material.second_moment", second_moment)?,
            damping: non_negative("material.damping", damping)?,
        })
    }

    /// A rectangular section `width` x `height` (m): `A = w h`, `I = w h^3 / 12` (bending
    /// across the height).
    pub fn rectangle(
        young: f64,
        density: f64,
        width: f64,
        height: f64,
        damping: f64,
    ) -> Result<Self> {
        let w = positive("section.width", width)?;
        let h = positive("section.height", height)?;
        Self::new(young, density, w * h, w * h * h * h / 12.0, damping)
    }

    /// Checks the fields again (they are public and may have been edited).
    pub fn validate(&self) -> Result<()> {
        Self::new(
            self.young,
            self.density,
            self.area,
            self.second_moment,
            self.damping,
        )
        .map(|_| ())
    }

    /// Axial stiffness `E A`, N.
    pub fn axial_stiffness(&self) -> f64 {
        self.young * self.area
    }

    /// Bending stiffness `E I`, N m^2.
    pub fn bending_stiffness(&self) -> f64 {
        self.young * self.second_moment
    }

    /// Mass per unit length `rho A`, kg/m.
    pub fn mass_per_length(&self) -> f64 {
        self.density * self.area
    }
}
