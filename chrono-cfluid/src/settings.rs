//! Settings of a [`ConstraintFluid`](crate::ConstraintFluid): resolution, kernel,
//! compliance, free-surface treatment, viscosity, domain.

use chrono_core::error::{ChronoError, Result, check_non_negative, check_positive};
use chrono_core::particles::KernelKind;
use serde::{Deserialize, Serialize};

pub use chrono_core::density_rows::SurfaceMode;

/// Settings of a [`ConstraintFluid`](crate::ConstraintFluid). SI units.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct CfluidSettings {
    /// Rest density `rho_0`, kg/m^3.
    pub rest_density: f64,
    /// Particle spacing `dp` of the initial cubic lattice, m.
    pub spacing: f64,
    /// Smoothing length over spacing, `h_k / dp` (the kernel support is `2 h_k`).
    pub h_over_dp: f64,
    /// The smoothing kernel.
    pub kernel: KernelKind,
    /// Compressibility `kappa = 1 / K`, 1/Pa (`>= 0`). Sets the compliance of each density
    /// row, `eps = kappa rho_0 / (h^2 m)` (h the step, m the particle mass), so that at
    /// rest a row holds `C_i = kappa p_i m_k / m` (`m_k` the kernel mass, 1.7 % below `m`
    /// at `h_k = 1.2 dp`; with `m` here the motion of a fluid without bodies does not
    /// depend on the particle mass): the fluid behaves as if its bulk modulus were
    /// `K`. Zero is the rigid constraint; a small positive value regularizes `N`
    /// (strictly convex problem, unique pressures, faster convergence) at the cost of a
    /// static compression `kappa p` (water: `kappa = 4.6e-10` 1/Pa).
    pub compressibility: f64,
    /// Free-surface treatment of the density rows.
    pub surface: SurfaceMode,
    /// XSPH velocity smoothing `epsilon` in `[0, 1]` applied after the solve (the
    /// viscosity of the model, see [`ConstraintFluid`](crate::ConstraintFluid)).
    pub xsph: f64,
    /// XSPH given as a viscosity `nu_x`, m^2/s (`>= 0`; 0 = off, then
    /// [`xsph`](Self::xsph) is the epsilon). When positive it replaces `xsph`: each step
    /// uses `eps = min(nu_x h / h_k^2, 1)` (`h` the step, `h_k` the smoothing length), so
    /// the smoothing's viscosity `~ eps h_k^2 / h` (the velocity of a particle relaxes
    /// toward its neighbours' by the fraction `eps` per step) does not grow as the step
    /// shrinks. `eps = 0.1` at `h_k = 1.2 dp` is `nu_x = 0.1 (1.2 dp)^2 / h`: 0.029 m^2/s
    /// at dp = 0.02 m, h = 2 ms.
    pub xsph_viscosity: f64,
    /// Whether the XSPH smoothing leaves the linear part of the velocity field alone
    /// (the gradient-corrected form, see `docs/validation-cfluid.md`): it then damps the
    /// particle noise but not a smooth flow at a free surface or a wall, where the plain
    /// form drags the surface particles toward their neighbours' one-sided mean.
    pub xsph_corrected: bool,
    /// The density rows' kernel-gradient correction (Bonet and Lok 1999): 0 = off (the
    /// rows are the exact gradients of the density constraints); otherwise each free
    /// particle's row coefficients are multiplied by the inverse of its moment matrix
    /// `M_i = -sum_j V F(r_ij) x_ij x_ij^T` where the smallest eigenvalue of `M_i` is at
    /// least this value (in `(0, 1]`; below it, at the free surface, the plain row is
    /// kept). The rows then read a shear of a disordered packing as no compression, which
    /// with the plain rows the projection removes as particle noise every step (the
    /// damping of the sloshing mode); see
    /// `chrono_core::density_rows::DensityField::row_corrected` and
    /// `docs/validation-cfluid.md` ("The rows' gradient correction").
    pub gradient_correction: f64,
    /// Whether a particle near a free surface holds its density at the reference of its
    /// truncated support, `C_i = rho_i / rho_0 - phi_i`, instead of `rho_i / rho_0 - 1`
    /// (`phi_i` in `(0, 1]` the fraction of a full kernel support its neighbourhood
    /// fills at the rest spacing, from the first moment of its neighbours by the
    /// planar-surface model of the lattice, see
    /// `chrono_core::density_rows::SupportModel` and
    /// `docs/validation-cfluid.md`). A row with `phi_i < 1` is unilateral (the free
    /// surface pushes but never pulls). Without it the surface layers' rows are slack
    /// until their truncated sums reach `rho_0`, so gravity packs them (the top layer of
    /// still water held 1.38 particles per `dp^2`) and the energy released feeds particle
    /// noise.
    pub surface_reference: bool,
    /// With [`SurfaceMode::OneSided`]: the largest density deficit `-C_i` (a fraction,
    /// `>= 0`) whose row stays **bilateral** and holds the density rate (`b_i` as for
    /// `C_i = 0`: the deficit is not pulled back, but the particle follows a body or
    /// neighbour that moves away). A larger deficit is a free-surface particle and gets
    /// the unilateral row. `0`, the default, makes every deficit unilateral. A diagnostic:
    /// next to the markers of a curved body the fluid starts 10-25 % short, where a
    /// unilateral row takes away the suction behind a moving body and most of its added
    /// mass; but the top layer of a flat free surface is short of only 18.7 % (Wendland
    /// C2, `h_k = 1.2 dp`), so a threshold that covers the first also makes that layer
    /// bilateral (`docs/validation-fsi.md`, "Constraint fluids").
    pub surface_deficit: f64,
    /// Largest stabilization rate `C_i / h` of a compressed particle, 1/s (`> 0`): a badly
    /// compressed start recovers at this rate instead of exploding.
    pub max_recovery_rate: f64,
    /// Position projection ("post-stabilization", Cline and Pai 2003; the Jacobi
    /// density projection of position-based fluids, Macklin and Mueller 2013): after
    /// `x += h v`, at most this many sweeps move the compressed particles apart,
    /// `dx = M^-1 grad C lambda` with `lambda_i = -C_i / |grad C_i|^2` for `C_i > 0`
    /// (relaxed by [`position_relaxation`](Self::position_relaxation)), until the
    /// largest compression is at most [`position_tolerance`](Self::position_tolerance).
    /// Velocities are not changed. It removes the drift of one step (the second-order
    /// change of the densities under `x += h v`, `~ (h v / h_k)^2`, which the velocity-
    /// level rows do not see), which otherwise bounds the step for a given compression.
    /// Default 0 (off). Markers (walls, bodies at their pose of the step) do not move.
    pub position_iterations: u32,
    /// Compression (`C_i`) at which the position projection stops.
    pub position_tolerance: f64,
    /// The density projection as a position-level CCP ("post-stabilization", Cline and
    /// Pai 2003; the density-invariant solve of DFSPH, Bender and Koschier 2015): after
    /// `x += h v`, the densities and the **exact** density rows `D_i = -grad C_i` at the
    /// new positions make a second problem of the same kind as the step's,
    ///
    /// ```text
    /// dx = M^-1 D lambda,   c_i = D_i' dx - C_i + eps_i lambda_i
    /// ```
    ///
    /// (`C_i(x + dx) ~ C_i - D_i' dx`; `eps_i` the step's compliance, so `lambda = h g`,
    /// N m s^2; bilateral or unilateral as the step's rows, by
    /// [`surface`](Self::surface) and the support fraction), solved by the CCP solver
    /// given to [`ConstraintFluid::set_projection_solver`](crate::ConstraintFluid::set_projection_solver)
    /// with at most this many iterations, to
    /// [`density_projection_tolerance`](Self::density_projection_tolerance); the positions
    /// move by `dx`, the pseudo-velocity `dx / h` is discarded (velocities unchanged).
    /// With [`gradient_correction`](Self::gradient_correction) it is the split of issue 29:
    /// the step's rows read the divergence by the corrected gradient, the drift of the
    /// density sums is removed along the exact one. Markers (walls, bodies at their pose
    /// of the step) do not move and have no rows here. 0 = off (the default); exclusive
    /// with [`position_iterations`](Self::position_iterations). Measured (issue 29,
    /// `docs/validation-cfluid.md`, "The split"): it removes the dam break's compression
    /// with corrected rows (20.7 % to 0.09 %) but also a first-order part of their shear,
    /// so part of the sloshing mode's damping comes back.
    pub density_projection: u32,
    /// Residual (chrono-ccp's, in units of `C_i`, dimensionless) at which the density
    /// projection's solver stops (`> 0`).
    pub density_projection_tolerance: f64,
    /// Relaxation factor of the Jacobi sweeps, in `(0, 1]`.
    pub position_relaxation: f64,
    /// The previous step's impulses times this factor warm-start the solver, in `[0, 1]`.
    pub warm_start_factor: f64,
    /// Lower corner of the domain of the neighbour grid, m (particles outside still work,
    /// only slower).
    pub domain_lower: [f64; 3],
    /// Upper corner of the domain, m.
    pub domain_upper: [f64; 3],
    /// Periodic axes (period `upper - lower`, at least twice the kernel support).
    pub periodic: [bool; 3],
    /// Whether the fluid particles are collision proxies of the rigid-body colliders
    /// (spheres of radius [`contact_radius_over_dp`](Self::contact_radius_over_dp)` dp`,
    /// frictional contact rows in the system's CCP). Default on; it costs nothing in a
    /// scene without colliders.
    pub body_contacts: bool,
    /// Radius of a particle's contact sphere over the spacing, in `[0, 1]`. Default `0.5`:
    /// a particle of the lattice fills a cube of side `dp`, so a wall face lies `dp / 2`
    /// from the centres of the first fluid layer, as it does for the marker walls and the
    /// body markers ([`ConstraintFluid::attach_body`](crate::ConstraintFluid::attach_body)).
    pub contact_radius_over_dp: f64,
    /// Whether each body marker ([`ConstraintFluid::attach_body`](crate::ConstraintFluid::attach_body))
    /// with fluid neighbours has a density row of its own, `C_k = rho_k / rho_0 - 1`
    /// (same compliance as the fluid's, always unilateral: a face is pushed by the fluid
    /// but never holds it in tension), on its fluid neighbours and its
    /// body: the marker then carries a pressure like a fluid particle and the pair forces
    /// across the body face are symmetric (`g_i + g_k`); without it the marker side has
    /// zero pressure. The row also keeps the fluid from crowding a face: a first fluid
    /// layer that packs more particles per area than the lattice raises the markers'
    /// densities, which the rows forbid. Default on: without it a submerged box of the
    /// fluid's density sank by 0.22 dp in 0.4 s (the layer under it packed; unit test
    /// `a_neutral_box_stays_where_it_is`), and `cfluid-floating-box` read its draft
    /// -28 % by the hydrostatic reading at `--quick` (-2.6 % with it;
    /// `docs/validation-cfluid.md`), for ~3-10 % more solver iterations.
    pub body_marker_rows: bool,
    /// Whether each wall marker with fluid neighbours has a density row of its own,
    /// `C_k = rho_k / rho_0 - 1`, unilateral like the body markers' rows (entries on its
    /// fluid neighbours and on the bodies of body-marker neighbours; the wall does not
    /// move). The same defect as at a body face without marker rows: the first fluid
    /// layer on a wall of rowless markers can pack more particles per area than the
    /// lattice (the floor layer under the floating box held 1.05 per `dp^2`).
    pub wall_marker_rows: bool,
    /// Coulomb friction coefficient of the fluid particles against bodies (`>= 0`; the
    /// contact takes the minimum of the two materials' coefficients). Default `0`: an
    /// inviscid fluid slips along a wall; the fluid's tangential stress on a body comes
    /// from the density rows of attached markers and from XSPH, not from friction.
    pub contact_friction: f64,
}

impl Default for CfluidSettings {
    fn default() -> Self {
        Self {
            rest_density: 1000.0,
            spacing: 0.01,
            h_over_dp: 1.2,
            kernel: KernelKind::WendlandC2,
            compressibility: 1e-9,
            surface: SurfaceMode::OneSided,
            surface_reference: false,
            surface_deficit: 0.0,
            xsph: 0.1,
            xsph_viscosity: 0.0,
            xsph_corrected: false,
            gradient_correction: 0.0,
            max_recovery_rate: 10.0,
            warm_start_factor: 1.0,
            position_iterations: 0,
            position_tolerance: 1e-4,
            position_relaxation: 0.5,
            density_projection: 0,
            density_projection_tolerance: 1e-9,
            domain_lower: [0.0; 3],
            domain_upper: [1.0; 3],
            periodic: [false; 3],
            body_contacts: true,
            contact_radius_over_dp: 0.5,
            contact_friction: 0.0,
            body_marker_rows: true,
            wall_marker_rows: false,
        }
    }
}

impl CfluidSettings {
    /// The smoothing length `h_k = h_over_dp * spacing`, m.
    pub fn smoothing_length(&self) -> f64 {
        self.h_over_dp * self.spacing
    }

    /// The XSPH epsilon of a step `h` (s): `min(xsph_viscosity h / h_k^2, 1)` when
    /// [`xsph_viscosity`](Self::xsph_viscosity) is positive, else [`xsph`](Self::xsph).
    pub fn xsph_epsilon(&self, h: f64) -> f64 {
        if self.xsph_viscosity > 0.0 {
            (self.xsph_viscosity * h / self.smoothing_length().powi(2)).min(1.0)
        } else {
            self.xsph
        }
    }

    /// Check every field; the error names it.
    pub fn validate(&self) -> Result<()> {
        check_positive("cfluid.rest_density", self.rest_density)?;
        check_positive("cfluid.spacing", self.spacing)?;
        check_positive("cfluid.h_over_dp", self.h_over_dp)?;
        if !(0.8..=3.0).contains(&self.h_over_dp) {
            return Err(ChronoError::invalid(
                "cfluid.h_over_dp",
                self.h_over_dp,
                "must be in [0.8, 3]",
            ));
        }
        check_non_negative("cfluid.compressibility", self.compressibility)?;
        check_non_negative("cfluid.xsph", self.xsph)?;
        if self.xsph > 1.0 {
            return Err(ChronoError::invalid(
                "cfluid.xsph",
                self.xsph,
                "must be in [0, 1]",
            ));
        }
        check_non_negative("cfluid.xsph_viscosity", self.xsph_viscosity)?;
        check_non_negative("cfluid.surface_deficit", self.surface_deficit)?;
        check_non_negative("cfluid.gradient_correction", self.gradient_correction)?;
        if self.gradient_correction > 1.0 {
            return Err(ChronoError::invalid(
                "cfluid.gradient_correction",
                self.gradient_correction,
                "must be 0 (off) or in (0, 1]",
            ));
        }
        check_positive("cfluid.max_recovery_rate", self.max_recovery_rate)?;
        check_positive("cfluid.position_tolerance", self.position_tolerance)?;
        check_positive("cfluid.position_relaxation", self.position_relaxation)?;
        if self.position_relaxation > 1.0 {
            return Err(ChronoError::invalid(
                "cfluid.position_relaxation",
                self.position_relaxation,
                "must be in (0, 1]",
            ));
        }
        check_positive(
            "cfluid.density_projection_tolerance",
            self.density_projection_tolerance,
        )?;
        if self.density_projection > 0 && self.position_iterations > 0 {
            return Err(ChronoError::invalid(
                "cfluid.density_projection",
                self.density_projection,
                format!(
                    "the CCP density projection and the Jacobi position projection \
                     (position_iterations = {}) are exclusive",
                    self.position_iterations
                ),
            ));
        }
        check_non_negative("cfluid.warm_start_factor", self.warm_start_factor)?;
        if self.warm_start_factor > 1.0 {
            return Err(ChronoError::invalid(
                "cfluid.warm_start_factor",
                self.warm_start_factor,
                "must be in [0, 1]",
            ));
        }
        check_non_negative("cfluid.contact_radius_over_dp", self.contact_radius_over_dp)?;
        if self.contact_radius_over_dp > 1.0 {
            return Err(ChronoError::invalid(
                "cfluid.contact_radius_over_dp",
                self.contact_radius_over_dp,
                "must be in [0, 1]",
            ));
        }
        check_non_negative("cfluid.contact_friction", self.contact_friction)?;
        let support = 2.0 * self.smoothing_length();
        for a in 0..3 {
            let (lo, hi) = (self.domain_lower[a], self.domain_upper[a]);
            if !(lo.is_finite() && hi.is_finite() && hi > lo) {
                return Err(ChronoError::invalid(
                    format!("cfluid.domain_upper[{a}]"),
                    hi,
                    format!("must be finite and > domain_lower[{a}] = {lo}"),
                ));
            }
            if self.periodic[a] && hi - lo < 2.0 * support * (1.0 - 1e-9) {
                return Err(ChronoError::invalid(
                    format!("cfluid.periodic[{a}]"),
                    hi - lo,
                    format!("the period must be at least twice the kernel support {support} m"),
                ));
            }
        }
        Ok(())
    }
}
