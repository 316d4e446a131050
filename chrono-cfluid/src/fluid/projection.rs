//! The position projection of
//! [`CfluidSettings::position_iterations`](crate::settings::CfluidSettings::position_iterations):
//! after the position update, compressed particles are pushed apart (velocities unchanged)
//! until the largest compression is at most `position_tolerance`.

use super::ConstraintFluid;
use crate::density::FluidField;
use chrono_core::error::Result;

impl ConstraintFluid {
    /// The position projection (after `x += h v`): Jacobi sweeps until the largest compression is at most
    /// `position_tolerance`. Records the sweeps and the compression left.
    pub(super) fn project_positions(&mut self) -> Result<()> {
        self.projection = (0, f64::NAN);
        let iters = self.settings.position_iterations;
        if iters == 0 {
            return Ok(());
        }
        let n = self.n_fluid;
        let mut rho = std::mem::take(&mut self.proj_rho);
        let mut lambda = std::mem::take(&mut self.proj_lambda);
        let mut dx = std::mem::take(&mut self.vel_scratch);
        rho.resize(n, 0.0);
        lambda.resize(n, 0.0);
        dx.resize(n, [0.0; 3]);
        let (tol, relax) = (
            self.settings.position_tolerance,
            self.settings.position_relaxation,
        );
        let mut sweeps = 0;
        let mut worst;
        loop {
            self.refresh_neighbors()?;
            let field = self.field();
            worst = field.projection(&mut rho, &mut lambda);
            if worst <= tol || sweeps >= iters {
                break;
            }
            field.projection_step(&lambda, relax, &mut dx);
            sweeps += 1;
            let s = &self.settings;
            for a in 0..3 {
                let (lo, hi) = (s.domain_lower[a], s.domain_upper[a]);
                for (x, d) in self.pos[a][..n].iter_mut().zip(&dx) {
                    *x += d[a];
                    if s.periodic[a] {
                        *x = lo + (*x - lo).rem_euclid(hi - lo);
                    }
                }
            }
        }
        self.projection = (sweeps, worst);
        self.proj_rho = rho;
        self.proj_lambda = lambda;
        self.vel_scratch = dx;
        Ok(())
    }

    /// The position projection of the last step: sweeps done and the largest compression
    /// left (NaN when the projection is off).
    pub fn last_projection(&self) -> (u32, f64) {
        self.projection
    }
}
