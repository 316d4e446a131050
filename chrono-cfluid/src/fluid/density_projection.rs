//! The density projection of
//! [`CfluidSettings::density_projection`](crate::settings::CfluidSettings::density_projection):
//! after the position update, a position-level CCP with the exact density rows at the new
//! positions, solved by a chrono-ccp solver, moves the particles so that the densities are
//! back at their reference (velocities unchanged: the pseudo-velocity is discarded).
//!
//! With `D_i = -grad C_i` (the exact row, [`DensityField::row`]), `M` the particles' mass
//! and the particles moved by `dx = M^-1 D lambda`, the linearized constraint after the
//! move is `C_i(x + dx) ~ C_i - D_i' dx`, so the projection's row is
//!
//! ```text
//! c_i = D_i' dx - C_i + eps_i lambda_i       (= 0 bilateral, or 0 <= lambda_i ⊥ c_i >= 0)
//! ```
//!
//! the velocity-level row of the step times `h` with `dx = h v` and `lambda = h g`
//! (so the compliance `eps_i` is the step's): [`push_density_row`] with `h = 1` and no cap
//! on the rate, which also gives the rows the step's free-surface treatment.
//! References: M. B. Cline and D. K. Pai, "Post-stabilization for rigid body simulation
//! with contact and constraints", ICRA 2003 (a position-level projection after the
//! velocity-level step, pseudo-velocities discarded); J. Bender and D. Koschier,
//! "Divergence-free smoothed particle hydrodynamics", SCA 2015 (DFSPH: a divergence-free
//! solve for the velocities and a separate density-invariant one for the positions).

use chrono_core::descriptor::{
    BlockId, CcpProblem, CcpSolver, ConstraintRows, RowEntry, Variables,
};
use chrono_core::error::{ChronoError, Result};
use chrono_core::item::StepContext;

use super::ConstraintFluid;
use chrono_core::density_rows::{RowBuf, SurfaceMode, compliance, push_density_row};

/// The solver, problem and scratch of the density projection, kept across steps.
#[derive(Default)]
pub(super) struct DensityProjection {
    /// The chrono-ccp solver ([`ConstraintFluid::set_projection_solver`]).
    pub(super) solver: Option<Box<dyn CcpSolver>>,
    vars: Variables,
    rows: ConstraintRows,
    problem: CcpProblem,
    bufs: Vec<RowBuf>,
    rho: Vec<f64>,
    phi: Vec<f64>,
    /// Multipliers of the last projection by particle (the warm start), N m s^2.
    lambda: Vec<f64>,
    gamma: Vec<f64>,
    k: Vec<f64>,
    dx: Vec<f64>,
    /// What the last projection did.
    pub(super) last: ProjectionReport,
}

/// What one density projection did ([`ConstraintFluid::last_density_projection`]).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ProjectionReport {
    /// Solver iterations.
    pub iterations: usize,
    /// The solver's residual at the end (units of `C_i`).
    pub residual: f64,
    /// Largest `C_i = rho_i / rho_0 - phi_i` before the projection (after `x += h v`).
    pub max_compression_before: f64,
    /// Largest displacement of a particle, m.
    pub max_displacement: f64,
}

impl ConstraintFluid {
    /// The CCP solver of the density projection
    /// ([`CfluidSettings::density_projection`](crate::CfluidSettings::density_projection)),
    /// e.g. `chrono_ccp::Apgd`; its tolerance and iteration cap are set from the settings
    /// at each projection. Needed (and only used) when the projection is on.
    pub fn set_projection_solver(&mut self, solver: Box<dyn CcpSolver>) {
        self.dproj.solver = Some(solver);
    }

    /// What the last density projection did (all zero when it is off).
    pub fn last_density_projection(&self) -> ProjectionReport {
        self.dproj.last
    }

    /// The density projection after `x += h v` (the step `ctx.h`, s). Errors: no solver
    /// set (names `cfluid.density_projection`), a non-finite problem.
    pub(super) fn project_densities(&mut self, ctx: &StepContext) -> Result<()> {
        let iters = self.settings.density_projection;
        self.dproj.last = ProjectionReport::default();
        if iters == 0 {
            return Ok(());
        }
        let mut p = std::mem::take(&mut self.dproj);
        let out = self.project_with(&mut p, ctx);
        self.dproj = p;
        out
    }

    fn project_with(&mut self, p: &mut DensityProjection, ctx: &StepContext) -> Result<()> {
        let s = self.settings.clone();
        let h = ctx.h;
        let Some(solver) = p.solver.as_mut() else {
            return Err(ChronoError::invalid(
                "cfluid.density_projection",
                s.density_projection,
                "the density projection needs a solver: ConstraintFluid::set_projection_solver",
            ));
        };
        {
            let st = solver.settings_mut();
            st.tolerance = s.density_projection_tolerance;
            st.max_iterations = s.density_projection as usize;
        }
        let n = self.n_fluid;
        self.refresh_neighbors()?;
        p.rho.resize(n, 0.0);
        p.phi.resize(n, 1.0);
        p.bufs.resize_with(n, RowBuf::default);
        p.lambda.resize(n, 0.0);
        {
            let field = self.field();
            field.densities(&mut p.rho);
            if let Some(model) = &self.support_model {
                field.support_fractions(model, &mut p.phi);
            }
            field.rows(&mut p.bufs);
        }
        p.vars.clear();
        for _ in 0..n {
            p.vars.add(self.mass_op.clone());
        }
        p.rows.clear();
        let eps = compliance(s.compressibility, s.rest_density, h, self.mass);
        let mut worst = f64::NEG_INFINITY;
        let mut entries: Vec<RowEntry> = Vec::new();
        for (i, buf) in p.bufs.iter().enumerate() {
            entries.clear();
            for (k, &j) in buf.particles.iter().enumerate() {
                entries.push(RowEntry {
                    block: BlockId(j),
                    coefs: &buf.coefs[3 * k..3 * k + 3],
                });
            }
            let (rho, phi) = (p.rho[i], p.phi[i]);
            let c = rho / s.rest_density - phi;
            worst = worst.max(c);
            let surface = if phi < 1.0 {
                SurfaceMode::Unilateral
            } else {
                s.surface
            };
            push_density_row(
                &mut p.rows,
                &entries,
                c,
                1.0,
                eps,
                0.0,
                surface,
                f64::INFINITY,
            );
        }
        drop(entries);
        p.k.clear();
        p.k.resize(3 * n, 0.0);
        p.problem.assemble(&p.vars, &p.rows, &p.k)?;
        // the rows were pushed in particle order, one each
        p.gamma.clear();
        p.gamma
            .extend(p.lambda.iter().map(|l| s.warm_start_factor * l));
        let stats = solver.solve(&p.problem, &mut p.gamma);
        if let Some(i) = p.gamma.iter().position(|g| !g.is_finite()) {
            return Err(self.non_finite(ctx, i, "density projection multiplier"));
        }
        p.lambda.copy_from_slice(&p.gamma);
        p.dx.resize(3 * n, 0.0);
        p.problem.velocities(&p.gamma, &mut p.dx);
        let mut largest = 0.0f64;
        for a in 0..3 {
            let (lo, hi) = (s.domain_lower[a], s.domain_upper[a]);
            for (i, x) in self.pos[a][..n].iter_mut().enumerate() {
                *x += p.dx[3 * i + a];
                if s.periodic[a] {
                    *x = lo + (*x - lo).rem_euclid(hi - lo);
                }
            }
        }
        for d in p.dx.chunks_exact(3) {
            largest = largest.max((d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt());
        }
        p.last = ProjectionReport {
            iterations: stats.iterations,
            residual: stats.residual,
            max_compression_before: worst,
            max_displacement: largest,
        };
        Ok(())
    }
}
