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
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum SolidModel {
    /// St. Venant–Kirchhoff: Hooke's law between the Green–Lagrange strain
    /// `E = (F^T F - I)/2` and the second Piola–Kirchhoff stress (`svk` in serde form).
    #[default]
    #[serde(rename = "svk")]
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

/// Linear elastic material and cross-section of the fully parameterized ANCF beam
/// ([`AncfBeam`](crate::element::AncfBeam)). Section axes: `y` along the node gradient
/// `r_y`, `z` along `r_z`, origin at the centroid (doubly symmetric sections: the
/// products `∫ y dA`, `∫ z dA`, `∫ y z dA` vanish).
///
/// Stiffnesses per unit reference length, each acting on one strain measure of the
/// element (see its docs):
/// - `E A` on the axial strain and on the stretch of `r_y`, `r_z` (the cross-section
///   deformation of the continuum with `nu = 0`); `G A` on the shear of `r_y` against
///   `r_z`;
/// - `k G A` on the two transverse shear strains (`k`: shear correction factor);
/// - `E I_y`, `E I_z` on the bending curvatures (`I_y = ∫ z^2 dA`: deflection along
///   `z`; `I_z = ∫ y^2 dA`: deflection along `y`);
/// - `G J` on the twist rate (`J`: the St. Venant torsion constant of the section, which
///   the linear cross-section field of the ANCF element cannot produce itself: without
///   warping it would give the polar moment `I_y + I_z`, too stiff for any non-circular
///   section).
///
/// `G = E / (2 (1 + nu))`. Poisson coupling between the axial and the cross-section
/// strains is left out on purpose (the "Poisson locking" remedy of the structural
/// mechanics formulation, Gerstmayr, Matikainen & Mikkola 2008): a beam's cross-section
/// is free to contract, and the linear cross-section field of the element cannot.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BeamSection {
    /// Young's modulus `E`, Pa.
    pub young: f64,
    /// Shear modulus `G`, Pa.
    pub shear_modulus: f64,
    /// Density `rho`, kg/m^3.
    pub density: f64,
    /// Area `A`, m^2.
    pub area: f64,
    /// `I_y = ∫ z^2 dA`, m^4 (bending with deflection along `z`).
    pub iy: f64,
    /// `I_z = ∫ y^2 dA`, m^4 (bending with deflection along `y`).
    pub iz: f64,
    /// Torsion constant `J`, m^4.
    pub torsion: f64,
    /// Shear correction factor `k` of the transverse shear, in (0, 1].
    pub shear_factor: f64,
}

impl BeamSection {
    /// A validated section: every value finite and > 0, `shear_factor` in (0, 1].
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        young: f64,
        shear_modulus: f64,
        density: f64,
        area: f64,
        iy: f64,
        iz: f64,
        torsion: f64,
        shear_factor: f64,
    ) -> Result<Self> {
        let k = positive("section.shear_factor", shear_factor)?;
        if k > 1.0 {
            return Err(crate::error::FeaError::invalid(
                "section.shear_factor",
                k,
                "must be in (0, 1]",
            ));
        }
        Ok(Self {
            young: positive("section.young", young)?,
            shear_modulus: positive("section.shear_modulus", shear_modulus)?,
            density: positive("section.density", density)?,
            area: positive("section.area", area)?,
            iy: positive("section.iy", iy)?,
            iz: positive("section.iz", iz)?,
            torsion: positive("section.torsion", torsion)?,
            shear_factor: k,
        })
    }

    /// A solid rectangle `width` (along `y`) x `height` (along `z`), m, of an isotropic
    /// material (`E`, `nu`, `rho`): `A = w h`, `I_y = w h^3 / 12`, `I_z = h w^3 / 12`,
    /// `k = 10 (1 + nu) / (12 + 11 nu)` (Cowper 1966) and the St. Venant torsion constant
    /// `J = beta a b^3` (`a >= b` the long and short sides) with the series of Timoshenko
    /// & Goodier (1970, sec. 109):
    ///
    /// ```text
    /// beta = 1/3 (1 - 192 b / (pi^5 a) sum_{n odd} tanh(n pi a / (2 b)) / n^5)
    /// ```
    ///
    /// (a square: `J = 0.1406 a^4`).
    pub fn rectangle(
        young: f64,
        poisson: f64,
        density: f64,
        width: f64,
        height: f64,
    ) -> Result<Self> {
        let w = positive("section.width", width)?;
        let h = positive("section.height", height)?;
        if !(poisson.is_finite() && poisson > -1.0 && poisson < 0.5) {
            return Err(crate::error::FeaError::invalid(
                "material.poisson",
                poisson,
                "must be in the open interval (-1, 0.5)",
            ));
        }
        let young = positive("material.young", young)?;
        let g = young / (2.0 * (1.0 + poisson));
        let k = 10.0 * (1.0 + poisson) / (12.0 + 11.0 * poisson);
        Self::new(
            young,
            g,
            density,
            w * h,
            w * h.powi(3) / 12.0,
            h * w.powi(3) / 12.0,
            rectangle_torsion_constant(w, h),
            k,
        )
    }

    /// The same section with the torsion constant `torsion` (m^4).
    pub fn with_torsion(self, torsion: f64) -> Result<Self> {
        Self::new(
            self.young,
            self.shear_modulus,
            self.density,
            self.area,
            self.iy,
            self.iz,
            torsion,
            self.shear_factor,
        )
    }

    /// The same section with the shear correction factor `k`.
    pub fn with_shear_factor(self, k: f64) -> Result<Self> {
        Self::new(
            self.young,
            self.shear_modulus,
            self.density,
            self.area,
            self.iy,
            self.iz,
            self.torsion,
            k,
        )
    }

    /// Checks the fields again (they are public and may have been edited).
    pub fn validate(&self) -> Result<()> {
        self.with_torsion(self.torsion).map(|_| ())
    }

    /// Mass per unit length `rho A`, kg/m.
    pub fn mass_per_length(&self) -> f64 {
        self.density * self.area
    }
}

/// St. Venant torsion constant of a solid `w` x `h` rectangle, m^4 (Timoshenko & Goodier
/// 1970, sec. 109; the series converges like `n^-5`, 50 odd terms are far below `1e-12`).
pub fn rectangle_torsion_constant(w: f64, h: f64) -> f64 {
    let (a, b) = if w >= h { (w, h) } else { (h, w) };
    let pi = std::f64::consts::PI;
    let sum: f64 = (0..50)
        .map(|k| {
            let n = (2 * k + 1) as f64;
            (n * pi * a / (2.0 * b)).tanh() / n.powi(5)
        })
        .sum();
    a * b.powi(3) / 3.0 * (1.0 - 192.0 * b / (pi.powi(5) * a) * sum)
}
