//! The [`ConstraintFluid`] physics item.

use chrono_core::descriptor::{
    BlockId, CcpProblem, ConstraintRows, MassOperator, RowEntry, RowId, Variables,
};
use chrono_core::error::{ChronoError, Result};
use chrono_core::item::{PhysicsItem, StepContext};
use chrono_core::particles::{CellGrid, GridConfig, Kernel, NeighborList};

use crate::density::{Field, RowBuf};
use crate::geometry::lattice_mass;
use crate::settings::{CfluidSettings, SurfaceMode};

/// A constraint fluid (H. Mazhar, "Parallel multi-body dynamics with frictional contact
/// and constraint fluids", PhD thesis, UW-Madison 2016; the seed's "Alternative Approach:
/// Constrained Fluids"): fluid particles are 3-dof point masses of the system's CCP, and
/// incompressibility is one holonomic constraint per particle,
///
/// ```text
/// C_i(x) = rho_i / rho_0 - 1,     rho_i = m W(0) + sum_j m W(|x_i - x_j|)
/// ```
///
/// (SPH summation over fluid particles and wall markers with a chrono-core kernel, the
/// neighbours from the chrono-core cell grid), enforced at the velocity level with the
/// stabilization `C_i / h`. Each particle contributes one row, written with
/// `D_i = -grad C_i` (1/m; entries `(m/rho_0) grad W_ij`, see [`crate::density`]) so that
/// its multiplier `g_i` (N m s) is a pressure impulse, positive when it pushes:
///
/// ```text
/// c_i = D_i' v + b_i + eps_i g_i,   b_i = -min(C_i / h, max_recovery_rate),
/// eps_i = kappa rho_0 / (h^2 m)
/// ```
///
/// bilateral (`c_i = 0`) or unilateral (`0 <= g_i ⊥ c_i >= 0`) according to
/// [`SurfaceMode`]. After a solve, `C_i(t + h) ~ kappa p_i` (the compliance makes the fluid
/// as compressible as one of bulk modulus `1 / kappa`), and the pressure is
/// `p_i = g_i rho_0 / (h m)` (Pa; [`pressures`](Self::pressures)): the force on particle
/// `j` is `-sum_i (g_i / h) grad_j C_i`, which with `g_i / h = p_i m / rho_0` is the
/// symmetric SPH pressure force `-m sum_i m (p_i + p_j) / rho_0^2 grad W`.
///
/// **Viscosity** is an XSPH velocity smoothing applied after the solve (Monaghan 1989):
/// `v_i <- v_i + eps sum_j (2 m / (rho_i + rho_j)) (v_j - v_i) W_ij` over fluid
/// neighbours, then `x <- x + h v` with the smoothed velocity (symplectic Euler). It damps
/// the relative motion of neighbours (an artificial viscosity of order
/// `eps h_k^2 / h`), conserves momentum (the pair weights are symmetric), and perturbs
/// the constraint velocities by `O(eps)`, which the next step's stabilization removes.
///
/// **Walls** are fixed marker particles (no variables) that enter the density sum and
/// the self term of the Jacobian: a fluid particle cannot compress against a wall, and
/// the wall needs no contact rows. Use at least [`wall_layers`](crate::wall_layers)
/// layers so the support is full.
///
/// **Warm start**: the last impulses times
/// [`warm_start_factor`](CfluidSettings::warm_start_factor), by particle, through
/// [`PhysicsItem::warm_start`].
///
/// Allocation: after the first step, a step allocates nothing unless the neighbour
/// counts grow (the grid, the neighbour list, the per-row buffers and the row-entry
/// scratch are kept). Density, rows and XSPH are rayon-parallel over particles.
pub struct ConstraintFluid {
    name: String,
    settings: CfluidSettings,
    kernel: Kernel,
    mass: f64,
    mass_op: MassOperator,
    n_fluid: usize,
    /// Positions of fluid particles then wall markers (structure of arrays), m.
    pos: [Vec<f64>; 3],
    vel: Vec<[f64; 3]>,
    rho: Vec<f64>,
    gamma: Vec<f64>,
    row_ids: Vec<RowId>,
    first_block: Option<BlockId>,
    grid: CellGrid,
    nbrs: NeighborList,
    rows: Vec<RowBuf>,
    entries: Vec<RowEntry<'static>>,
    vel_scratch: Vec<[f64; 3]>,
    last_h: f64,
    neighbors_fresh: bool,
}

/// Re-types an empty vector of row entries for another borrow: the allocation is kept
/// (in-place collect of a same-layout type), so the scratch survives across steps
/// without borrowing the item.
fn recycle<'b>(mut v: Vec<RowEntry<'_>>) -> Vec<RowEntry<'b>> {
    v.clear();
    v.into_iter().map(|_| unreachable!()).collect()
}

fn check_points(field: &str, pts: &[[f64; 3]]) -> Result<()> {
    for (i, p) in pts.iter().enumerate() {
        for a in 0..3 {
            if !p[a].is_finite() {
                return Err(ChronoError::invalid(
                    format!("{field}[{i}][{a}]"),
                    p[a],
                    "must be finite",
                ));
            }
        }
    }
    Ok(())
}

impl ConstraintFluid {
    /// A fluid of particles at `fluid` (at rest) in walls of markers at `walls`, m. The
    /// particle mass is [`lattice_mass`] (the lattice of `settings.spacing` sums to
    /// `rho_0`). Errors name the bad field: settings, an empty fluid, a non-finite
    /// position.
    pub fn new(
        name: impl Into<String>,
        settings: CfluidSettings,
        fluid: &[[f64; 3]],
        walls: &[[f64; 3]],
    ) -> Result<Self> {
        settings.validate()?;
        if fluid.is_empty() {
            return Err(ChronoError::invalid(
                "fluid",
                0,
                "a constraint fluid needs at least one particle",
            ));
        }
        check_points("fluid", fluid)?;
        check_points("walls", walls)?;
        let kernel = Kernel::new(settings.kernel, settings.smoothing_length(), 3)?;
        let mass = lattice_mass(&kernel, settings.spacing, settings.rest_density);
        let mass_op = MassOperator::particle(mass)?;
        let config = GridConfig::bounded(
            kernel.support(),
            settings.domain_lower,
            settings.domain_upper,
        )
        .with_periodic(settings.periodic);
        let grid = CellGrid::new(config)?;
        let n_fluid = fluid.len();
        let pos = std::array::from_fn(|a| fluid.iter().chain(walls).map(|p| p[a]).collect());
        Ok(Self {
            name: name.into(),
            kernel,
            mass,
            mass_op,
            n_fluid,
            pos,
            vel: vec![[0.0; 3]; n_fluid],
            rho: vec![settings.rest_density; n_fluid],
            gamma: vec![0.0; n_fluid],
            row_ids: Vec::with_capacity(n_fluid),
            first_block: None,
            grid,
            nbrs: NeighborList::new(),
            rows: vec![RowBuf::default(); n_fluid],
            entries: Vec::new(),
            vel_scratch: vec![[0.0; 3]; n_fluid],
            last_h: 0.0,
            neighbors_fresh: false,
            settings,
        })
    }

    /// The settings.
    pub fn settings(&self) -> &CfluidSettings {
        &self.settings
    }

    /// The kernel.
    pub fn kernel(&self) -> &Kernel {
        &self.kernel
    }

    /// Mass of every particle (fluid and markers), kg.
    pub fn particle_mass(&self) -> f64 {
        self.mass
    }

    /// Number of fluid particles.
    pub fn n_fluid(&self) -> usize {
        self.n_fluid
    }

    /// Number of wall markers.
    pub fn n_walls(&self) -> usize {
        self.pos[0].len() - self.n_fluid
    }

    /// Position of fluid particle `i`, m.
    pub fn position(&self, i: usize) -> [f64; 3] {
        [self.pos[0][i], self.pos[1][i], self.pos[2][i]]
    }

    /// Velocities of the fluid particles, m/s.
    pub fn velocities(&self) -> &[[f64; 3]] {
        &self.vel
    }

    /// Set the velocity of every fluid particle (e.g. an initial condition), m/s; the
    /// error names the first non-finite entry.
    pub fn set_velocities(&mut self, v: &[[f64; 3]]) -> Result<()> {
        if v.len() != self.n_fluid {
            return Err(ChronoError::invalid(
                "velocities.len()",
                v.len(),
                format!("must equal the fluid particle count {}", self.n_fluid),
            ));
        }
        check_points("velocities", v)?;
        self.vel.copy_from_slice(v);
        Ok(())
    }

    /// Densities of the fluid particles, kg/m^3, at the positions of the start of the
    /// last step (or of the last [`compute_densities`](Self::compute_densities)).
    pub fn densities(&self) -> &[f64] {
        &self.rho
    }

    /// Recompute the neighbours and densities at the current positions (diagnostics:
    /// the density after the last step).
    pub fn compute_densities(&mut self) -> Result<&[f64]> {
        self.refresh_neighbors()?;
        let mut rho = std::mem::take(&mut self.rho);
        self.field().densities(&mut rho);
        self.rho = rho;
        Ok(&self.rho)
    }

    /// The density-row impulses of the last step, N m s (one per fluid particle, `>= 0`
    /// where it pushes).
    pub fn impulses(&self) -> &[f64] {
        &self.gamma
    }

    /// The density rows of the last step, one per fluid particle (map them to global rows
    /// with [`CcpProblem::row_index`]).
    pub fn row_ids(&self) -> &[RowId] {
        &self.row_ids
    }

    /// Pressure of fluid particle `i` from the last step, `p_i = g_i rho_0 / (h m)`, Pa.
    pub fn pressure(&self, i: usize) -> f64 {
        if self.last_h > 0.0 {
            self.gamma[i] * self.settings.rest_density / (self.last_h * self.mass)
        } else {
            0.0
        }
    }

    /// The largest compression `max_i (rho_i / rho_0 - 1)` over the current densities
    /// (`<= 0` when nothing is compressed).
    pub fn max_compression(&self) -> f64 {
        let r0 = self.settings.rest_density;
        self.rho
            .iter()
            .map(|r| r / r0 - 1.0)
            .fold(f64::NEG_INFINITY, f64::max)
    }

    /// Kinetic energy of the fluid, J.
    pub fn kinetic_energy(&self) -> f64 {
        0.5 * self.mass
            * self
                .vel
                .iter()
                .map(|v| v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
                .sum::<f64>()
    }

    fn field(&self) -> Field<'_> {
        Field {
            kernel: &self.kernel,
            mass: self.mass,
            rho_0: self.settings.rest_density,
            grid: &self.grid,
            pos: [&self.pos[0], &self.pos[1], &self.pos[2]],
            nbrs: &self.nbrs,
            n_fluid: self.n_fluid,
        }
    }

    fn refresh_neighbors(&mut self) -> Result<()> {
        let pos = [&self.pos[0][..], &self.pos[1][..], &self.pos[2][..]];
        self.grid.build(pos)?;
        self.grid
            .neighbor_list(pos, self.kernel.support(), &mut self.nbrs)?;
        self.neighbors_fresh = true;
        Ok(())
    }

    fn non_finite(&self, ctx: &StepContext, i: usize, what: &str) -> ChronoError {
        ChronoError::NonFinite {
            item: format!("constraint fluid \"{}\" (particle {i})", self.name),
            step: ctx.step,
            time: ctx.time,
            what: what.into(),
        }
    }
}

impl PhysicsItem for ConstraintFluid {
    fn name(&self) -> &str {
        &self.name
    }

    fn add_variables(&mut self, vars: &mut Variables) {
        let first = vars.add(self.mass_op.clone());
        for _ in 1..self.n_fluid {
            vars.add(self.mass_op.clone());
        }
        self.first_block = Some(first);
    }

    fn load_momentum(&self, ctx: &StepContext, vars: &Variables, k: &mut [f64]) {
        let Some(first) = self.first_block else {
            return;
        };
        let off = vars.offset(first);
        let g = ctx.gravity;
        for (i, v) in self.vel.iter().enumerate() {
            for a in 0..3 {
                k[off + 3 * i + a] += self.mass * (v[a] + ctx.h * g[a]);
            }
        }
    }

    fn add_constraints(
        &mut self,
        ctx: &StepContext,
        _vars: &Variables,
        rows: &mut ConstraintRows,
    ) -> Result<()> {
        let Some(first) = self.first_block else {
            return Ok(());
        };
        self.refresh_neighbors()?;
        let mut rho = std::mem::take(&mut self.rho);
        let mut bufs = std::mem::take(&mut self.rows);
        {
            let field = self.field();
            field.densities(&mut rho);
            field.rows(&mut bufs);
        }
        self.rho = rho;
        self.rows = bufs;
        if let Some(i) = self.rho.iter().position(|r| !r.is_finite()) {
            return Err(self.non_finite(ctx, i, "density"));
        }

        let h = ctx.h;
        let s = &self.settings;
        let eps = s.compressibility * s.rest_density / (h * h * self.mass);
        let mut entries = recycle(std::mem::take(&mut self.entries));
        self.row_ids.clear();
        for (i, buf) in self.rows.iter().enumerate() {
            entries.clear();
            for (k, &p) in buf.particles.iter().enumerate() {
                entries.push(RowEntry {
                    block: BlockId(first.0 + p),
                    coefs: &buf.coefs[3 * k..3 * k + 3],
                });
            }
            let c = self.rho[i] / s.rest_density - 1.0;
            let id = match s.surface {
                SurfaceMode::OneSided if c < 0.0 => rows.push_unilateral(&entries, -c / h, eps),
                SurfaceMode::OneSided => {
                    rows.push_bilateral(&entries, -(c / h).min(s.max_recovery_rate), eps)
                }
                SurfaceMode::Unilateral => {
                    rows.push_unilateral(&entries, -(c / h).min(s.max_recovery_rate), eps)
                }
                SurfaceMode::Clamped => {
                    rows.push_bilateral(&entries, -(c.max(0.0) / h).min(s.max_recovery_rate), eps)
                }
            };
            self.row_ids.push(id);
        }
        self.entries = recycle(entries);
        Ok(())
    }

    fn warm_start(&self, problem: &CcpProblem, gamma: &mut [f64]) {
        if self.row_ids.len() != self.n_fluid {
            return;
        }
        let f = self.settings.warm_start_factor;
        for (id, g) in self.row_ids.iter().zip(&self.gamma) {
            // a row that became unilateral is projected by the solver
            gamma[problem.row_index(*id)] = f * g;
        }
    }

    fn update(
        &mut self,
        ctx: &StepContext,
        vars: &Variables,
        v: &[f64],
        problem: &CcpProblem,
        gamma: &[f64],
    ) -> Result<()> {
        let Some(first) = self.first_block else {
            return Ok(());
        };
        let off = vars.offset(first);
        for (i, vi) in self.vel.iter_mut().enumerate() {
            *vi = [v[off + 3 * i], v[off + 3 * i + 1], v[off + 3 * i + 2]];
        }
        for (g, id) in self.gamma.iter_mut().zip(&self.row_ids) {
            *g = gamma[problem.row_index(*id)];
        }
        if let Some(i) = self
            .vel
            .iter()
            .position(|v| v.iter().any(|x| !x.is_finite()))
        {
            return Err(self.non_finite(ctx, i, "velocity after the solve"));
        }
        if self.settings.xsph > 0.0 && self.neighbors_fresh {
            let mut out = std::mem::take(&mut self.vel_scratch);
            self.field()
                .xsph(self.settings.xsph, &self.rho, &self.vel, &mut out);
            self.vel_scratch = std::mem::replace(&mut self.vel, out);
        }
        let h = ctx.h;
        let s = &self.settings;
        for a in 0..3 {
            let (lo, hi) = (s.domain_lower[a], s.domain_upper[a]);
            let period = hi - lo;
            for (x, v) in self.pos[a][..self.n_fluid].iter_mut().zip(&self.vel) {
                *x += h * v[a];
                if s.periodic[a] {
                    *x = lo + (*x - lo).rem_euclid(period);
                }
            }
        }
        if let Some(i) = (0..self.n_fluid).find(|&i| (0..3).any(|a| !self.pos[a][i].is_finite())) {
            return Err(self.non_finite(ctx, i, "position after the step"));
        }
        self.last_h = h;
        self.neighbors_fresh = false;
        Ok(())
    }
}
