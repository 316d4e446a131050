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

/// How a solid element turns its deformation gradient `F` into stress (see
/// [`Tet4`](crate::element::Tet4) for the equations).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SolidModel {
    /// St. Venant–Kirchhoff: Hooke's law between the Green–Lagrange strain
    /// `E = (F^T F - I)/2` and the second Piola–Kirchhoff stress.
    #[default]
    StVenantKirchhoff,
    /// Corotational linear: Hooke's law on the stretch `U - I` of the polar
    /// decomposition `F = R U`, rotated by `R` (the small-strain element carried by the
    /// element's rotation).
    Corotational,
}

/// Isotropic linear elastic solid material of the tetrahedron
/// ([`Tet4`](crate::element::Tet4)), used in the St. Venant–Kirchhoff law
/// `S = lambda tr(E) I + 2 mu E` (second Piola–Kirchhoff stress `S` from the
/// Green–Lagrange strain `E`; or, with [`SolidModel::Corotational`], the same Hooke's
/// law on the corotated stretch) with the Lamé constants
///
/// ```text
/// lambda = E nu / ((1 + nu)(1 - 2 nu)),   mu = G = E / (2 (1 + nu))
/// ```
///
/// `damping` is the stiffness-proportional (Rayleigh beta) coefficient in seconds, for a
/// dynamic stepper; statics ignore it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolidMaterial {
    /// Young's modulus `E`, Pa.
    pub young: f64,
    /// Poisson's ratio `nu`, in (-1, 0.5).
    pub poisson: f64,
    /// Density `rho`, kg/m^3.
    pub density: f64,
    /// Stiffness-proportional damping coefficient, s (0: undamped).
    pub damping: f64,
    /// The constitutive model (default St. Venant–Kirchhoff).
    pub model: SolidModel,
}

impl SolidMaterial {
    /// A validated material: `young` and `density` finite and > 0, `poisson` in the open
    /// interval (-1, 0.5) (the bounds make the bulk or shear modulus infinite or zero),
    /// `damping` finite and >= 0. The error names the field and value.
    pub fn new(young: f64, poisson: f64, density: f64, damping: f64) -> Result<Self> {
        let young = positive("material.young", young)?;
        if !(poisson.is_finite() && poisson > -1.0 && poisson < 0.5) {
            return Err(crate::error::FeaError::invalid(
                "material.poisson",
                poisson,
                "must be in the open interval (-1, 0.5)",
            ));
        }
        Ok(Self {
            young,
            poisson,
            density: positive("material.density", density)?,
            damping: non_negative("material.damping", damping)?,
            model: SolidModel::StVenantKirchhoff,
        })
    }

    /// The same material with constitutive model `model`.
    pub fn with_model(self, model: SolidModel) -> Self {
        Self { model, ..self }
    }

    /// Checks the fields again (they are public and may have been edited).
    pub fn validate(&self) -> Result<()> {
        Self::new(self.young, self.poisson, self.density, self.damping).map(|_| ())
    }

    /// The Lamé constants `(lambda, mu)`, Pa.
    pub fn lame(&self) -> (f64, f64) {
        let (e, nu) = (self.young, self.poisson);
        (
            e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)),
            e / (2.0 * (1.0 + nu)),
        )
    }

    /// Shear modulus `G = E / (2 (1 + nu))`, Pa.
    pub fn shear_modulus(&self) -> f64 {
        self.lame().1
    }
}
