//! The split's pressure (`docs/mpm.md`, "The split"): the volumetric part of the stress as
//! constraint-fluid density rows on the markers, one CCP per step solved by chrono-ccp's
//! APGD, while MPM carries the deviatoric stress only (Stomakhin et al., "Augmented MPM for
//! phase-change and varied materials", ACM TOG 33(4), 2014, split the stress this way; the
//! rows are H. Mazhar's constraint fluid, PhD thesis, UW-Madison 2016, the seed's
//! "Split Pressure and Shear").
//!
//! Each marker `p` is a 3-dof block of its own mass `m_p`; its row is the density
//! constraint of [`chrono_core::density_rows`] (the same code as chrono-cfluid's),
//!
//! ```text
//! C_p = rho_p / rho_0 - 1,   rho_p = m_k W(0) + sum_q m_k W(|x_p - x_q|)
//! M (v - v*) = D gamma,   D_p' v - min(C_p / dt, max_rate) + eps_p gamma_p = 0   (or >= 0)
//! eps_p = kappa rho_0 / (dt^2 m_p),   kappa = 1 / K
//! ```
//!
//! with `v*` the markers' velocities after G2P (deviatoric stress, gravity, walls), `m_k`
//! the kernel mass of the marker lattice (spacing `dp`; [`lattice_mass`]) so that the
//! initial lattice is at `C = 0`, and the fixed wall markers (no variables; lattice layers
//! beyond the grid's walls) in the sums. A row with `C_p < 0` (a free surface, a marker
//! pulled apart) is unilateral ([`SurfaceMode::OneSided`]): the material never pulls at
//! the rows' side (a soil, a mud); the wall markers have unilateral rows of their own.
//! The marker pressure is read from the impulses with the lattice's gradient
//! normalization ([`PressureRows::pressure`]).

use chrono_core::density_rows::{
    DensityField, RowBuf, SupportModel, SurfaceMode, compliance, lattice_mass, push_density_row,
};
use chrono_core::descriptor::{
    BlockId, CcpProblem, CcpSolver, ConstraintRows, MassOperator, RowEntry, RowId, SolverSettings,
    Variables,
};
use chrono_core::particles::{CellGrid, GridConfig, Kernel, KernelKind, NeighborList};

use rayon::prelude::*;

use crate::error::{MpmError, Result, invalid};
use crate::markers::Markers;
use crate::rigid::RigidBody;
pub use crate::row_markers::{box_slab_markers, lattice_gradient_moment, slab_wall_markers};
use crate::timings::lap;

mod settings;
pub use settings::{PressureSettings, RowsNorm, StrainFrom};

/// The pressure rows of an MPM body in the split mode (see the module documentation).
#[derive(Clone, Debug)]
pub struct PressureRows {
    settings: PressureSettings,
    kernel: Kernel,
    /// Kernel mass `m_k` of the marker lattice, kg (kg/m with the 2-D kernel).
    kernel_mass: f64,
    /// `-(m_k / rho_0) a`, the lattice's gradient normalization (see [`Self::pressure`]).
    gradient_scale: f64,
    /// Wall markers (fixed, in the sums), m.
    walls: [Vec<f64>; 3],
    pos: [Vec<f64>; 3],
    grid: CellGrid,
    nbrs: NeighborList,
    bufs: Vec<RowBuf>,
    rho: Vec<f64>,
    /// The markers' support fractions `phi_p` of the last step (1 without
    /// [`PressureSettings::surface_reference`]) and the model that gives them.
    phi: Vec<f64>,
    support_model: Option<SupportModel>,
    ids: Vec<RowId>,
    /// Row buffers, densities (kg/m^3) and impulses (N m s) of the wall markers, and the
    /// wall markers that have a row this step.
    wall_bufs: Vec<RowBuf>,
    wall_rho: Vec<f64>,
    wall_gamma: Vec<f64>,
    wall_ids: Vec<(u32, RowId)>,
    /// Coulomb friction coefficient (-) and unit normal (into the material) of each wall
    /// marker ([`PressureRows::set_wall_friction`]; 0: frictionless).
    wall_friction: Vec<f64>,
    wall_normal: Vec<[f64; 3]>,
    /// Markers attached to rigid bodies: offsets from the centre (m), the body's index,
    /// each body's centre at the step (m), and their rows as the walls'.
    body_local: Vec<[f64; 3]>,
    body_owner: Vec<u32>,
    body_origin: Vec<[f64; 3]>,
    marker_bufs: Vec<RowBuf>,
    marker_rho: Vec<f64>,
    marker_gamma: Vec<f64>,
    marker_ids: Vec<(u32, RowId)>,
    /// Each marker's row impulse of the last step, N m s.
    gamma: Vec<f64>,
    /// Each marker's pressure of the last step, Pa.
    pressure: Vec<f64>,
    /// Its kernel average, Pa ([`PressureRows::smoothed_pressure`]).
    smoothed: Vec<f64>,
    vars: Variables,
    rows: ConstraintRows,
    problem: CcpProblem,
    solver: chrono_ccp::Apgd,
    k: Vec<f64>,
    v: Vec<f64>,
    gamma_all: Vec<f64>,
    /// Each marker's velocity change by the rows at the last step, m/s.
    dv: Vec<[f64; 3]>,
    /// Iterations and residual (m/s) of the last solve.
    last: (usize, f64),
    /// Wall time, s, of the assembly, the solve, what follows it and the neighbour search,
    /// summed over steps ([`MpmBody::timings`](crate::MpmBody::timings)).
    pub(crate) timing: [f64; 4],
}

impl PressureRows {
    /// Rows with `settings` for markers inside the region `[lower, upper]` (m; the
    /// neighbour grid's box, markers outside still work, slower), with fixed wall markers
    /// at `walls` (m; on the markers' lattice beyond the grid's walls, at least
    /// `chrono_core::particles::lattice::wall_layers(h_over_dp)` layers). Errors name the
    /// field.
    pub fn new(
        settings: PressureSettings,
        lower: [f64; 3],
        upper: [f64; 3],
        walls: &[[f64; 3]],
    ) -> Result<Self> {
        settings.validate()?;
        for (i, w) in walls.iter().enumerate() {
            if !w.iter().all(|c| c.is_finite()) {
                return Err(invalid(
                    &format!("pressure.walls[{i}]"),
                    format!("{w:?}"),
                    "must be finite",
                ));
            }
        }
        let h_k = settings.h_over_dp * settings.spacing;
        let kernel = Kernel::new(KernelKind::WendlandC2, h_k, settings.dim)?;
        let kernel_mass = lattice_mass(&kernel, settings.spacing, settings.rest_density);
        let grid = CellGrid::new(GridConfig::bounded(kernel.support(), lower, upper))?;
        let a = lattice_gradient_moment(&kernel, settings.spacing);
        Ok(Self {
            settings,
            kernel,
            kernel_mass,
            gradient_scale: -kernel_mass / settings.rest_density * a,
            walls: std::array::from_fn(|a| walls.iter().map(|w| w[a]).collect()),
            pos: Default::default(),
            grid,
            nbrs: NeighborList::new(),
            bufs: Vec::new(),
            rho: Vec::new(),
            phi: Vec::new(),
            support_model: settings
                .surface_reference
                .then(|| SupportModel::new(&kernel, settings.spacing)),
            ids: Vec::new(),
            wall_bufs: vec![RowBuf::default(); walls.len()],
            wall_rho: vec![settings.rest_density; walls.len()],
            wall_gamma: vec![0.0; walls.len()],
            wall_ids: Vec::new(),
            wall_friction: vec![0.0; walls.len()],
            wall_normal: vec![[0.0; 3]; walls.len()],
            body_local: Vec::new(),
            body_owner: Vec::new(),
            body_origin: Vec::new(),
            marker_bufs: Vec::new(),
            marker_rho: Vec::new(),
            marker_gamma: Vec::new(),
            marker_ids: Vec::new(),
            gamma: Vec::new(),
            pressure: Vec::new(),
            smoothed: Vec::new(),
            vars: Variables::new(),
            rows: ConstraintRows::new(),
            problem: CcpProblem::new(),
            solver: chrono_ccp::Apgd::new(SolverSettings {
                tolerance: settings.tolerance,
                max_iterations: settings.max_iterations,
                ..SolverSettings::default()
            }),
            k: Vec::new(),
            v: Vec::new(),
            gamma_all: Vec::new(),
            dv: Vec::new(),
            last: (0, 0.0),
            timing: [0.0; 4],
        })
    }

    /// The settings.
    pub fn settings(&self) -> &PressureSettings {
        &self.settings
    }

    /// Each marker's pressure of the last step, Pa (positive in compression):
    /// `p_p = gamma_p (m_k / rho_0) |a| / (V_p dt)`, with `a = (1/dim) sum_j F(r_j) r_j^2`
    /// over the marker lattice (`F = W'/r`) and `V_p` the marker's volume. With it the rows'
    /// impulses on a lattice under a linear pressure field are exactly `-V_p grad p dt`
    /// (the row coefficients are `(m_k/rho_0) F x`, and `sum_j F x_j x_j' = a I` on the
    /// lattice), so `p` is the pressure that balances the markers' weight; it differs from
    /// chrono-cfluid's `gamma rho_0 / (dt m_k)` by the lattice's two normalizations,
    /// `(m_k / rho_0)^2 |a| / V` (1 for the continuous kernel).
    pub fn pressure(&self) -> &[f64] {
        &self.pressure
    }

    /// Each marker's pressure of the last step averaged over its kernel support, Pa:
    /// `pbar_p = sum_q W_pq p_q / sum_q W_pq` over the marker itself, its neighbours and
    /// the wall markers (their rows' pressure, read as the markers'). The markers' own
    /// pressures carry a staircase on the lattice (pairs of layers share a value, `rho g
    /// dp / 2` either side of the hydrostatic line; `docs/mpm.md`), a mode the rows do
    /// not see; a pressure-dependent yield surface evaluated with it is weaker in the low
    /// layers, and a sand layer on a gentle slope creeps there. The average removes that
    /// mode (exact for a linear field on a full support) and is what the Drucker–Prager
    /// return takes.
    pub fn smoothed_pressure(&self) -> &[f64] {
        &self.smoothed
    }

    /// Switches [`PressureSettings::surface_reference`] on or off (from the next step).
    pub fn set_surface_reference(&mut self, on: bool) {
        self.settings.surface_reference = on;
        self.support_model = on.then(|| SupportModel::new(&self.kernel, self.settings.spacing));
    }

    /// Each marker's support fraction `phi_p` of the last step (its row's reference
    /// `rho_0 phi_p`; all 1 without [`PressureSettings::surface_reference`]).
    pub fn support_fractions(&self) -> &[f64] {
        &self.phi
    }

    /// Each marker's density of the last step (at the step's start), kg/m^3.
    pub fn density(&self) -> &[f64] {
        &self.rho
    }

    /// The largest compression `max_p C_p` at the last step's start (0 when none),
    /// `C_p = rho_p / rho_0 - phi_p` ([`Self::support_fractions`]).
    pub fn max_compression(&self) -> f64 {
        let r0 = self.settings.rest_density;
        self.rho
            .iter()
            .zip(&self.phi)
            .fold(0.0, |m, (r, phi)| m.max(r / r0 - phi))
    }

    /// APGD's iterations and residual (RMS, 1/s) at the last step.
    pub fn last_solve(&self) -> (usize, f64) {
        self.last
    }

    /// The tolerance APGD was given at the last step (RMS, 1/s): `tolerance`, or
    /// `tolerance / sqrt(n)` under [`RowsNorm::L2`].
    pub fn solver_tolerance(&self) -> f64 {
        self.solver.settings().tolerance
    }

    /// The fixed wall markers.
    pub fn wall_marker_count(&self) -> usize {
        self.walls[0].len()
    }

    /// The rows of the last step's CCP (the markers' and the wall and body markers' with
    /// neighbours).
    pub fn rows(&self) -> usize {
        self.problem.n_rows()
    }

    /// Checks the markers against the settings: every `mass / volume0` is the rest density
    /// (to 1e-9). The error names the marker.
    pub fn check_markers(&self, markers: &Markers) -> Result<()> {
        let r0 = self.settings.rest_density;
        for p in 0..markers.len() {
            let rho = markers.mass[p] / markers.volume0[p];
            if (rho / r0 - 1.0).abs() > 1e-9 {
                return Err(invalid(
                    &format!("marker[{p}].mass / volume0"),
                    rho,
                    &format!("must equal pressure.rest_density = {r0} kg/m^3"),
                ));
            }
        }
        Ok(())
    }

    /// Coulomb friction `friction` (>= 0, -) on the wall markers that `select` picks by
    /// their position (m), whose wall has the unit normal `normal` (into the material).
    /// The rows' normal impulse of those markers on a marker `p` (the pair impulses
    /// `J_pw = -(m_k/rho_0) F(r_pw) x_pw (g_p + g_w)`, `x_pw = x_p - x_w`, of its own row
    /// and the wall markers') then also brakes its tangential velocity relative to the
    /// (still) wall, after the rows' solve: `|v_t| <- max(|v_t| - friction J_n / m_p, 0)`,
    /// `J_n = sum_w max(J_pw . n, 0)`. In the split the pressure that presses the material
    /// on a wall is the rows', not the grid's (whose contact sees the gravity and the
    /// deviatoric stress only): without this a Coulomb wall of the grid holds back only a
    /// fraction of the material's weight. Errors name the field.
    pub fn set_wall_friction(
        &mut self,
        friction: f64,
        normal: [f64; 3],
        select: impl Fn(&[f64; 3]) -> bool,
    ) -> Result<()> {
        if !(friction.is_finite() && friction >= 0.0) {
            return Err(invalid(
                "pressure.wall_friction",
                friction,
                "must be finite and >= 0",
            ));
        }
        let len = normal.iter().map(|c| c * c).sum::<f64>().sqrt();
        if !(len.is_finite() && len > 0.0) {
            return Err(invalid(
                "pressure.wall_normal",
                format!("{normal:?}"),
                "must be a finite non-zero vector",
            ));
        }
        let n = normal.map(|c| c / len);
        for k in 0..self.walls[0].len() {
            let x = [self.walls[0][k], self.walls[1][k], self.walls[2][k]];
            if select(&x) {
                self.wall_friction[k] = friction;
                self.wall_normal[k] = n;
            }
        }
        Ok(())
    }

    /// The walls' Coulomb friction after the rows' solve ([`Self::set_wall_friction`]):
    /// brakes the markers' tangential velocities and adds the change to `self.dv`.
    fn wall_friction(&mut self, markers: &mut Markers) {
        let n = markers.len();
        let s = self.kernel_mass / self.settings.rest_density;
        for p in 0..n {
            let xp = [self.pos[0][p], self.pos[1][p], self.pos[2][p]];
            let mut cap = 0.0;
            let mut normal = nalgebra::Vector3::zeros();
            for &q in self.nbrs.neighbors(p) {
                let q = q as usize;
                if !(n..n + self.wall_friction.len()).contains(&q) {
                    continue;
                }
                let w = q - n;
                let mu = self.wall_friction[w];
                if mu == 0.0 {
                    continue;
                }
                let d = self
                    .grid
                    .displacement(xp, [self.pos[0][q], self.pos[1][q], self.pos[2][q]]);
                let r = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
                let f = -s * self.kernel.grad_factor(r) * (self.gamma[p] + self.wall_gamma[w]);
                let nw = nalgebra::Vector3::from(self.wall_normal[w]);
                let jn = f * (d[0] * nw[0] + d[1] * nw[1] + d[2] * nw[2]);
                if jn > 0.0 {
                    cap += mu * jn;
                    normal += nw * jn;
                }
            }
            if cap <= 0.0 {
                continue;
            }
            let nrm = normal.normalize();
            let v = markers.v[p];
            let vt = v - nrm * v.dot(&nrm);
            let t = vt.norm();
            if t == 0.0 {
                continue;
            }
            let dv = -vt * (cap / markers.mass[p]).min(t) / t;
            markers.v[p] += dv;
            for a in 0..3 {
                self.dv[p][a] += dv[a];
            }
        }
    }

    /// Attaches markers fixed to rigid body `rigid` (its index in `MpmBody::rigid`) at the
    /// offsets `local` from its centre (m; e.g. [`box_slab_markers`]): they enter the sums
    /// at the body's position, move at its surface velocity (known: kinematic bodies), have
    /// unilateral rows of their own, and the rows' impulses on them are added to the
    /// body's reaction ([`RigidBody::impulse`](crate::rigid::RigidBody::impulse)). Errors
    /// name the field.
    pub fn attach_rigid(&mut self, rigid: usize, local: &[[f64; 3]]) -> Result<()> {
        for (i, w) in local.iter().enumerate() {
            if !w.iter().all(|c| c.is_finite()) {
                return Err(invalid(
                    &format!("pressure.rigid_markers[{i}]"),
                    format!("{w:?}"),
                    "must be finite",
                ));
            }
        }
        for l in local {
            self.body_local.push(*l);
            self.body_owner.push(rigid as u32);
            self.marker_bufs.push(RowBuf::default());
            self.marker_rho.push(self.settings.rest_density);
            self.marker_gamma.push(0.0);
        }
        Ok(())
    }

    /// The rows' solve of one step `dt` (s): the markers' velocities `markers.v` (`v*` of
    /// G2P) become `v* + M^-1 D gamma`; the rows' impulses on the attached rigid bodies are
    /// added to their reactions. `step` names the step in an error (a non-finite density
    /// or velocity, a body marker on a body that does not exist).
    pub fn solve(
        &mut self,
        markers: &mut Markers,
        rigid: &mut [RigidBody],
        dt: f64,
        step: u64,
        time: f64,
    ) -> Result<()> {
        let mut t = std::time::Instant::now();
        let n = markers.len();
        let s = self.settings;
        if let Some(&o) = self.body_owner.iter().find(|&&o| o as usize >= rigid.len()) {
            return Err(invalid(
                "pressure.attach_rigid.rigid",
                o,
                "no such rigid body on the MPM body",
            ));
        }
        self.body_origin.clear();
        self.body_origin.extend(
            rigid
                .iter()
                .map(|r| [r.position.x, r.position.y, r.position.z]),
        );
        for a in 0..3 {
            self.pos[a].clear();
            self.pos[a].extend(markers.x.iter().map(|x| x[a]));
            self.pos[a].extend_from_slice(&self.walls[a]);
            for (l, &o) in self.body_local.iter().zip(&self.body_owner) {
                self.pos[a].push(self.body_origin[o as usize][a] + l[a]);
            }
        }
        let n_static = n + self.walls[0].len();
        let pos = [&self.pos[0][..], &self.pos[1][..], &self.pos[2][..]];
        self.grid.build(pos)?;
        // A wall marker farther than the support from the box around the markers has no
        // free neighbour, so no row: its list is left empty (it still appears in the
        // markers' lists). The rows and densities that are used are the same bits.
        let support = self.kernel.support();
        let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        for x in &markers.x {
            for a in 0..3 {
                lo[a] = lo[a].min(x[a]);
                hi[a] = hi[a].max(x[a]);
            }
        }
        let reach = support * (1.0 + 1e-9);
        let near =
            |i: usize| (0..3).all(|a| pos[a][i] >= lo[a] - reach && pos[a][i] <= hi[a] + reach);
        self.grid.neighbor_list_rows(
            pos,
            support,
            &mut self.nbrs,
            |i| i < n || i >= n_static || near(i),
            |_, _| true,
        )?;
        lap(&mut t, &mut self.timing[3]);
        self.bufs.resize(n, RowBuf::default());
        self.rho.resize(n, 0.0);
        let field = DensityField {
            kernel: &self.kernel,
            mass: self.kernel_mass,
            rho_0: s.rest_density,
            grid: &self.grid,
            pos,
            nbrs: &self.nbrs,
            n_free: n,
            n_static,
            marker_owner: &self.body_owner,
            body_origin: &self.body_origin,
        };
        field.densities(&mut self.rho);
        self.phi.clear();
        self.phi.resize(n, 1.0);
        if let Some(model) = &self.support_model {
            field.support_fractions(model, &mut self.phi);
        }
        field.rows(&mut self.bufs);
        field.wall_rows(&mut self.wall_bufs, &mut self.wall_rho);
        field.marker_rows(&mut self.marker_bufs, &mut self.marker_rho);
        if let Some(p) = self.rho.iter().position(|r| !r.is_finite()) {
            return Err(MpmError::Diverged {
                marker: p,
                step,
                time,
                what: "non-finite density in the pressure rows".into(),
            });
        }

        self.vars.clear();
        self.k.clear();
        let mut first = None;
        for p in 0..n {
            let id = self.vars.add(MassOperator::particle(markers.mass[p])?);
            first.get_or_insert(id);
            let mv = markers.v[p] * markers.mass[p];
            self.k.extend_from_slice(&[mv[0], mv[1], mv[2]]);
        }
        let Some(first) = first else {
            return Ok(());
        };
        // `D' v` of a body block: the body's known surface velocity (kinematic bodies).
        let known = |bodies: &[(u32, [f64; 6])]| -> f64 {
            let mut k = 0.0;
            for (slot, c) in bodies {
                let r = &rigid[*slot as usize];
                for a in 0..3 {
                    k += c[a] * r.velocity[a] + c[3 + a] * r.angular_velocity[a];
                }
            }
            k
        };
        self.rows.clear();
        self.ids.clear();
        let mut entries: Vec<RowEntry> = Vec::new();
        for p in 0..n {
            let buf = &self.bufs[p];
            entries.clear();
            for (j, &q) in buf.particles.iter().enumerate() {
                entries.push(RowEntry {
                    block: BlockId(first.0 + q),
                    coefs: &buf.coefs[3 * j..3 * j + 3],
                });
            }
            let c = self.rho[p] / s.rest_density - self.phi[p];
            let eps = compliance(s.compressibility, s.rest_density, dt, markers.mass[p]);
            let id = push_density_row(
                &mut self.rows,
                &entries,
                c,
                dt,
                eps,
                known(&buf.bodies),
                // a surface marker's row (phi < 1, `surface_reference`) pushes but never
                // pulls, as chrono-cfluid's
                if self.phi[p] < 1.0 {
                    SurfaceMode::Unilateral
                } else {
                    SurfaceMode::OneSided
                },
                s.max_recovery_rate,
            );
            self.ids.push(id);
        }
        // The wall markers' and the body markers' own rows (chrono-cfluid's
        // `wall_marker_rows`, `body_marker_rows`), unilateral: a wall or a body pushes with
        // a pressure of its own, so the pair forces across it are `g_i + g_k` as inside;
        // without them the first layer carries twice the hydrostatic pressure and the
        // layers above alternate.
        let m_ref = markers.mass.iter().sum::<f64>() / n as f64;
        let eps = compliance(s.compressibility, s.rest_density, dt, m_ref);
        for (bufs, rho, ids) in [
            (&self.wall_bufs, &self.wall_rho, &mut self.wall_ids),
            (&self.marker_bufs, &self.marker_rho, &mut self.marker_ids),
        ] {
            ids.clear();
            for (k, buf) in bufs.iter().enumerate() {
                if buf.particles.is_empty() {
                    continue;
                }
                entries.clear();
                for (j, &q) in buf.particles.iter().enumerate() {
                    entries.push(RowEntry {
                        block: BlockId(first.0 + q),
                        coefs: &buf.coefs[3 * j..3 * j + 3],
                    });
                }
                let c = rho[k] / s.rest_density - 1.0;
                let id = push_density_row(
                    &mut self.rows,
                    &entries,
                    c,
                    dt,
                    eps,
                    known(&buf.bodies),
                    SurfaceMode::Unilateral,
                    s.max_recovery_rate,
                );
                ids.push((k as u32, id));
            }
        }
        drop(entries);
        self.problem.assemble(&self.vars, &self.rows, &self.k)?;
        self.gamma_all.clear();
        self.gamma_all.resize(self.problem.n_rows(), 0.0);
        let f = s.warm_start_factor;
        if self.gamma.len() == n {
            for (id, g) in self.ids.iter().zip(&self.gamma) {
                self.gamma_all[self.problem.row_index(*id)] = f * g;
            }
        }
        for (ids, gamma) in [
            (&self.wall_ids, &self.wall_gamma),
            (&self.marker_ids, &self.marker_gamma),
        ] {
            for (k, id) in ids {
                self.gamma_all[self.problem.row_index(*id)] = f * gamma[*k as usize];
            }
        }
        if s.tolerance_norm == RowsNorm::L2 {
            // Chrono's Euclidean stop over this step's rows, as chrono-ccp's RMS
            self.solver.settings_mut().tolerance =
                s.tolerance / (self.problem.n_rows().max(1) as f64).sqrt();
        }
        lap(&mut t, &mut self.timing[0]);
        let stats = self.solver.solve(&self.problem, &mut self.gamma_all);
        self.last = (stats.iterations, stats.residual);
        lap(&mut t, &mut self.timing[1]);
        self.v.resize(3 * n, 0.0);
        self.problem.velocities(&self.gamma_all, &mut self.v);
        let off = self.vars.offset(first);
        self.dv.clear();
        for p in 0..n {
            let v = &self.v[off + 3 * p..off + 3 * p + 3];
            if !v.iter().all(|x| x.is_finite()) {
                return Err(MpmError::Diverged {
                    marker: p,
                    step,
                    time,
                    what: "non-finite velocity after the pressure rows".into(),
                });
            }
            let new = nalgebra::Vector3::new(v[0], v[1], v[2]);
            let d = new - markers.v[p];
            self.dv.push([d[0], d[1], d[2]]);
            markers.v[p] = new;
        }
        let gamma_all = &self.gamma_all;
        let problem = &self.problem;
        self.gamma.clear();
        self.gamma
            .extend(self.ids.iter().map(|id| gamma_all[problem.row_index(*id)]));
        for (ids, gamma) in [
            (&self.wall_ids, &mut self.wall_gamma),
            (&self.marker_ids, &mut self.marker_gamma),
        ] {
            gamma.fill(0.0);
            for (k, id) in ids {
                gamma[*k as usize] = gamma_all[problem.row_index(*id)];
            }
        }
        if self.wall_friction.iter().any(|&f| f > 0.0) {
            self.wall_friction(markers);
        }
        // The rows' impulses on the bodies, `g_i [lin; ang]_b` (about the body's centre):
        // the body gives the material the opposite.
        if !self.body_owner.is_empty() {
            let mut push_body = |bodies: &[(u32, [f64; 6])], g: f64| {
                for (slot, c) in bodies {
                    let r = &mut rigid[*slot as usize];
                    let lin = nalgebra::Vector3::new(c[0], c[1], c[2]) * g;
                    let ang = nalgebra::Vector3::new(c[3], c[4], c[5]) * g;
                    r.impulse -= lin;
                    r.total_impulse -= lin;
                    r.angular_impulse -= ang;
                    r.total_angular_impulse -= ang;
                }
            };
            for (p, buf) in self.bufs.iter().enumerate() {
                push_body(&buf.bodies, self.gamma[p]);
            }
            for (bufs, gamma) in [
                (&self.wall_bufs, &self.wall_gamma),
                (&self.marker_bufs, &self.marker_gamma),
            ] {
                for (buf, g) in bufs.iter().zip(gamma.iter()) {
                    if *g != 0.0 {
                        push_body(&buf.bodies, *g);
                    }
                }
            }
        }
        self.pressure.clear();
        let scale = self.gradient_scale / dt;
        self.pressure
            .extend((0..n).map(|p| self.gamma[p] * scale / markers.volume0[p]));
        self.smooth_pressure(scale / (markers.volume0.iter().sum::<f64>() / n as f64));
        lap(&mut t, &mut self.timing[2]);
        Ok(())
    }

    /// [`Self::smoothed_pressure`]; `wall_scale` turns a wall marker's impulse into its
    /// pressure (the markers' mean volume, Pa / (N m s)).
    fn smooth_pressure(&mut self, wall_scale: f64) {
        let n = self.pressure.len();
        let n_walls = self.wall_gamma.len();
        let (kernel, nbrs, grid, pos) = (&self.kernel, &self.nbrs, &self.grid, &self.pos);
        let (pressure, wall_gamma) = (&self.pressure, &self.wall_gamma);
        self.smoothed.resize(n, 0.0);
        self.smoothed
            .par_iter_mut()
            .enumerate()
            .for_each(|(p, out)| {
                let xp = [pos[0][p], pos[1][p], pos[2][p]];
                let w0 = kernel.w(0.0);
                let (mut num, mut den) = (w0 * pressure[p], w0);
                for &q in nbrs.neighbors(p) {
                    let q = q as usize;
                    let pq = if q < n {
                        pressure[q]
                    } else if q < n + n_walls {
                        wall_gamma[q - n] * wall_scale
                    } else {
                        continue;
                    };
                    let d = grid.displacement(xp, [pos[0][q], pos[1][q], pos[2][q]]);
                    let w = kernel.w((d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt());
                    num += w * pq;
                    den += w;
                }
                *out = num / den;
            });
    }

    /// Scales each marker's increment `dF_p` (after the step's strain increment,
    /// [`StrainFrom`]) so
    /// that the trial `J = det(dF_p F_E F_P)` is the rows' volume ratio at the step's
    /// start, `rho_0 / rho_p`: `dF_p <- (J_rows / J_trial)^(1/3) dF_p`, an isotropic
    /// factor, so the deviatoric part of the increment is kept (as F-bar with the rows'
    /// density as the volume measure). Only with
    /// [`PressureSettings::volume_from_rows`]; a non-positive `J_trial` is left for the
    /// return mapping to report.
    pub fn match_volume(&self, markers: &Markers, df: &mut [nalgebra::Matrix3<f64>]) {
        if !self.settings.volume_from_rows {
            return;
        }
        let r0 = self.settings.rest_density;
        let rho = &self.rho;
        df[..rho.len()]
            .par_iter_mut()
            .enumerate()
            .for_each(|(p, df)| {
                let j =
                    df.determinant() * markers.fe[p].determinant() * markers.fp[p].determinant();
                let target = r0 / rho[p];
                if j > 0.0 && target.is_finite() && target > 0.0 {
                    *df *= (target / j).cbrt();
                }
            });
    }

    /// Adds the rows' share of the step's velocity-gradient increment to each marker's
    /// `df` (`I + dt grad v` of G2P, from the grid velocity before the rows): `dt G_p` with
    /// the SPH gradient of the rows' velocity change `dv` (the wall markers' is 0),
    ///
    /// ```text
    /// G_p = sum_q (m_k / rho_0) (dv_q - dv_p) (grad_p W_pq)',   grad_p W_pq = F(r_pq) x_pq
    /// ```
    ///
    /// exact for a linear field on a full support. Without it `F_E` would follow the grid's
    /// velocity before the pressure, and at rest under gravity keep compressing next to a
    /// floor (the grid's `g dt` above a node held at 0, removed by the rows every step).
    /// Used with [`StrainFrom::GridPlusRows`] only: the B-spline and SPH gradients do not
    /// cancel next to a wall, so a bed at rest still strains (`docs/mpm.md`, "The mud
    /// bench"); the default is [`StrainFrom::FinalGrid`]. Call after
    /// [`solve`](Self::solve), before the positions move.
    pub fn add_velocity_gradient(&self, dt: f64, df: &mut [nalgebra::Matrix3<f64>]) {
        let n = self.dv.len();
        let v = self.kernel_mass / self.settings.rest_density;
        let grid = &self.grid;
        let pos = &self.pos;
        let (kernel, nbrs, dv) = (&self.kernel, &self.nbrs, &self.dv);
        df[..n].par_iter_mut().enumerate().for_each(|(p, df)| {
            let xp = [pos[0][p], pos[1][p], pos[2][p]];
            let mut g = nalgebra::Matrix3::zeros();
            for &q in nbrs.neighbors(p) {
                let q = q as usize;
                let d = grid.displacement(xp, [pos[0][q], pos[1][q], pos[2][q]]);
                let r = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
                let f = v * kernel.grad_factor(r);
                let dq = if q < n { dv[q] } else { [0.0; 3] };
                for a in 0..3 {
                    for b in 0..3 {
                        g[(a, b)] += (dq[a] - dv[p][a]) * f * d[b];
                    }
                }
            }
            *df += g * dt;
        });
    }
}
