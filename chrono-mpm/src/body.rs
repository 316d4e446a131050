//! An MPM body: markers of one material on a background grid, advanced by the explicit
//! MLS-free APIC scheme (Jiang, Schroeder, Selle, Teran & Stomakhin, "The affine
//! particle-in-cell method", ACM TOG 34(4), 2015):
//!
//! ```text
//! P2G:   m_i = sum_p w_ip m_p
//!        m_i v_i~ = sum_p w_ip m_p (v_p + C_p (x_i - x_p)) - dt sum_p V0_p tau_p grad w_ip
//! grid:  v_i = v_i~ / m_i + dt g,  then the wall conditions
//! G2P:   v_p = sum_i w_ip v_i,   C_p = 4/dx^2 sum_i w_ip v_i (x_i - x_p)^T
//!        F_E <- (I + dt sum_i v_i grad w_ip^T) F_E,  then the return mapping
//!        x_p <- x_p + dt v_p
//! ```
//!
//! with `tau = P F_E^T` the Kirchhoff stress (the grid force `-V0 P F^T grad w` of the
//! usual MPM). APIC, not PIC: the affine matrix `C` keeps the angular momentum and the
//! velocity gradients that PIC averages away, so an elastic body keeps its energy (the
//! elastic bar loses < 1 % in 10 periods, `docs/mpm.md`); without FLIP's noise.
//!
//! Parallel and reproducible: P2G *gathers* per active block (each block adds the markers
//! of its 8 neighbouring marker blocks in the sorted marker order), so no two threads
//! write one node and every node sums its markers in one fixed order, whatever the thread
//! count; the grid update and G2P are per node and per marker. The results are the same
//! bits for any thread count.

use nalgebra::{Matrix3, Vector3};
use rayon::prelude::*;

use crate::bspline::{Stencil, apic_d_inverse};
use crate::error::{MpmError, Result, invalid, positive};
use crate::fbar::FBar;
use crate::fold;
use crate::grid::{BLOCK, BLOCK3, GHOST, GridSpec, SparseGrid, Wall, key, unkey};
use crate::markers::Markers;
use crate::material::Material;
use crate::pressure::{PressureRows, PressureSettings};
use crate::rigid::RigidBody;
use crate::timings::{StepTimings, lap};
use std::time::Instant;

mod g2p;
mod grid_update;
mod mirror;
mod rigid_update;

/// Settings of an MPM body.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MpmSettings {
    /// Gravity, m/s^2 (Z up).
    pub gravity: [f64; 3],
    /// The CFL number of the explicit limit `dt <= cfl dx / (c + |v|max)`, with
    /// `c = sqrt((lambda + 2 mu) / rho)` the P-wave speed.
    pub cfl: f64,
    /// F-bar ([`crate::fbar`]): each marker's volume change of the step replaced by its
    /// volume-weighted average over the grid stencil, against volumetric locking in nearly
    /// incompressible or isochoric-plastic flow and a checkerboard of the markers' volume
    /// changes. Off by default.
    pub f_bar: FBar,
}

impl Default for MpmSettings {
    fn default() -> Self {
        Self {
            gravity: [0.0, 0.0, -9.81],
            cfl: 0.5,
            f_bar: FBar::Off,
        }
    }
}

/// What P2G needs of a marker, in sorted order (contiguous for the block gather).
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct P2gMarker {
    pub(crate) st: Stencil,
    /// Base node per axis shifted by GHOST.
    pub(crate) g0: [usize; 3],
    m: f64,
    /// m v.
    mv: [f64; 3],
    /// m C (row-major).
    mc: [[f64; 3]; 3],
    /// -dt V0 tau (row-major).
    a: [[f64; 3]; 3],
}

/// Per axis, the offsets `o` in `0..3` of a marker's stencil (first node `g0`) with
/// `lo <= g0 + o < lo + BLOCK`: the part of the stencil inside the grid block whose first
/// node is `lo`, as half-open ranges; `None` when the stencil misses the block.
#[inline]
pub(crate) fn stencil_in_block(g0: [usize; 3], lo: [usize; 3]) -> Option<[(usize, usize); 3]> {
    let mut r = [(0usize, 0usize); 3];
    for a in 0..3 {
        let from = lo[a].saturating_sub(g0[a]).min(3);
        let to = (lo[a] + BLOCK).saturating_sub(g0[a]).min(3);
        if from >= to {
            return None;
        }
        r[a] = (from, to);
    }
    Some(r)
}

/// An MPM body (see the module documentation).
#[derive(Clone, Debug)]
pub struct MpmBody {
    /// The markers (their arrays may be read and edited between steps).
    pub markers: Markers,
    /// Kinematic rigid bodies acting on the grid ([`crate::rigid`]), applied in order after
    /// the walls; their positions advance by `velocity dt` each step.
    pub rigid: Vec<RigidBody>,
    material: Material,
    spec: GridSpec,
    settings: MpmSettings,
    grid: SparseGrid,
    scratch: Vec<P2gMarker>,
    status: Vec<u8>,
    /// The step's velocity-gradient increment `I + dt grad v` per marker (G2P scratch),
    /// scaled by the F-bar factor when [`MpmSettings::f_bar`].
    df: Vec<Matrix3<f64>>,
    /// F-bar scratch: per marker `(V^n, V^n dJ)`, per node the weighted sums, then the
    /// nodal average ([`crate::fbar`]).
    vol_dj: Vec<[f64; 2]>,
    nodal_dj: Vec<[f64; 2]>,
    /// The FLIP fraction of the marker velocity update ([`MpmBody::set_flip`]).
    flip: f64,
    /// The split's pressure rows ([`MpmBody::set_pressure_rows`]); `None`: plain MPM.
    pressure: Option<Box<PressureRows>>,
    /// Wall time of the step's parts ([`MpmBody::timings`]).
    timings: StepTimings,
    steps: u64,
    time: f64,
}

/// The least markers of one parallel task (below it, rayon's task switching costs more
/// than the work; the results do not depend on it).
const MARKERS_PER_TASK: usize = 256;
/// The least grid blocks of one parallel task.
const BLOCKS_PER_TASK: usize = 8;

/// Why a marker failed in G2P.
const BAD_STATE: u8 = 1;
const BAD_PROJECTION: u8 = 2;
const BAD_VOLUME: u8 = 3;

impl MpmBody {
    /// A body of `material` on the grid `spec`; add markers through [`MpmBody::markers`].
    pub fn new(spec: GridSpec, material: Material, settings: MpmSettings) -> Result<Self> {
        // Re-check the public fields.
        GridSpec::new(spec.origin, spec.cells, spec.dx)?;
        positive("settings.cfl", settings.cfl)?;
        if settings.cfl > 1.0 {
            return Err(invalid("settings.cfl", settings.cfl, "must be <= 1"));
        }
        for (a, g) in settings.gravity.iter().enumerate() {
            if !g.is_finite() {
                return Err(invalid(
                    &format!("settings.gravity[{a}]"),
                    g,
                    "must be finite",
                ));
            }
        }
        Ok(Self {
            markers: Markers::new(),
            rigid: Vec::new(),
            material,
            spec,
            settings,
            grid: SparseGrid::default(),
            scratch: Vec::new(),
            status: Vec::new(),
            df: Vec::new(),
            vol_dj: Vec::new(),
            nodal_dj: Vec::new(),
            flip: 0.0,
            pressure: None,
            timings: StepTimings::default(),
            steps: 0,
            time: 0.0,
        })
    }

    /// The grid geometry.
    pub fn spec(&self) -> &GridSpec {
        &self.spec
    }

    /// The material.
    pub fn material(&self) -> &Material {
        &self.material
    }

    /// The settings.
    pub fn settings(&self) -> &MpmSettings {
        &self.settings
    }

    /// Sets the F-bar mode ([`MpmSettings::f_bar`]) for the following steps.
    pub fn set_f_bar(&mut self, mode: FBar) {
        self.settings.f_bar = mode;
    }

    /// Blends FLIP into the APIC velocity update for the following steps:
    ///
    /// ```text
    /// v_p <- sum_i w_ip v_i^{n+1} + flip (v_p^n - sum_i w_ip v_i^n)
    /// ```
    ///
    /// with `v_i^n` the grid velocity of the transfer alone (before the stress, gravity and
    /// the boundary conditions): the part of the marker's velocity the grid did not carry
    /// is kept, a fraction `flip` of it (`C_p` stays APIC's). 0 (the default) is APIC,
    /// which removes that part every step: an energy loss per step, not per unit time
    /// (Fei, Guo, Wu, Huang & Gao, "Revisiting integration in the material point method",
    /// ACM TOG 40(4), 2021, blend FLIP into APIC for it). Errors name `flip` outside
    /// `[0, 1]`.
    pub fn set_flip(&mut self, flip: f64) -> Result<()> {
        if !(flip.is_finite() && (0.0..=1.0).contains(&flip)) {
            return Err(invalid("flip", flip, "must lie in [0, 1]"));
        }
        self.flip = flip;
        Ok(())
    }

    /// Switches to the split (`pressure = rows`, `docs/mpm.md` "The split"): from the next
    /// step MPM carries the deviatoric Kirchhoff stress only, `tau - tr(tau)/3 I`, and the
    /// pressure comes from density rows on the markers ([`crate::pressure`]) with the fixed
    /// wall markers `walls` (m), solved after G2P and before the positions move. The
    /// time-step limit is then the shear wave's, `c = sqrt(4 mu / (3 rho))`. Errors name
    /// the field (settings, a marker whose `mass / volume0` is not the rest density, a
    /// dilatant Drucker–Prager flow, whose plastic volume change the rows' fixed rest
    /// density cannot follow). A Drucker–Prager sand's yield surface then takes the rows'
    /// pressure ([`crate::material::DruckerPrager::return_strain_at_pressure`]).
    pub fn set_pressure_rows(
        &mut self,
        settings: PressureSettings,
        walls: &[[f64; 3]],
    ) -> Result<()> {
        let dilatancy = self.material.plastic_dilatancy();
        if dilatancy != 0.0 {
            return Err(invalid(
                "material.dilatancy",
                dilatancy,
                "must be 0 in the split (pressure = rows): the rows' rest density is fixed",
            ));
        }
        let (lo, hi) = self.spec.admissible();
        let rows = PressureRows::new(settings, lo, hi, walls)?;
        rows.check_markers(&self.markers)?;
        self.pressure = Some(Box::new(rows));
        Ok(())
    }

    /// The split's pressure rows, if set, for attaching rigid-body markers
    /// ([`PressureRows::attach_rigid`]).
    pub fn pressure_rows_mut(&mut self) -> Option<&mut PressureRows> {
        self.pressure.as_deref_mut()
    }

    /// The split's pressure rows, if set ([`MpmBody::set_pressure_rows`]).
    pub fn pressure_rows(&self) -> Option<&PressureRows> {
        self.pressure.as_deref()
    }

    /// Wall time of the parts of the steps since the last [`MpmBody::reset_timings`]
    /// (the split's rows in three parts; zero there in plain MPM).
    pub fn timings(&self) -> StepTimings {
        let mut t = self.timings;
        if let Some(rows) = &self.pressure {
            let [a, s, p, nb] = rows.timing;
            t.rows_neighbours += nb;
            t.rows_assembly += a;
            t.rows_solve += s;
            t.rows_post += p;
        }
        t
    }

    /// Zeroes the [`MpmBody::timings`] (e.g. after a warm-up).
    pub fn reset_timings(&mut self) {
        self.timings = StepTimings::default();
        if let Some(rows) = &mut self.pressure {
            rows.timing = [0.0; 4];
        }
    }

    /// The sparse grid of the last step (active blocks, node masses).
    pub fn grid(&self) -> &SparseGrid {
        &self.grid
    }

    /// Steps taken.
    pub fn steps(&self) -> u64 {
        self.steps
    }

    /// Simulated time, s.
    pub fn time(&self) -> f64 {
        self.time
    }

    /// The explicit time-step limit `cfl dx / (c + |v|max)`, s, with `c` the largest
    /// P-wave speed `sqrt((lambda + 2 mu) / rho0)` over the markers (hardening included),
    /// or in the split the deviatoric one, `sqrt(4 mu / (3 rho0))`.
    pub fn stable_dt(&self) -> f64 {
        self.settings.cfl * self.spec.dx / self.wave_speed()
    }

    /// The largest `c + |v|` over the markers, m/s.
    pub fn wave_speed(&self) -> f64 {
        let mk = &self.markers;
        let mat = &self.material;
        let hardens = mat.hardens();
        let split = self.pressure.is_some();
        let id = Matrix3::identity();
        // max is exact and order-free: the same for any thread count.
        (0..mk.len())
            .into_par_iter()
            .with_min_len(MARKERS_PER_TASK)
            .map(|p| {
                let rho = mk.mass[p] / mk.volume0[p];
                let fp = if hardens { &mk.fp[p] } else { &id };
                let m = if split {
                    4.0 / 3.0 * mat.shear_modulus(fp)
                } else {
                    mat.p_modulus(fp)
                };
                (m / rho).sqrt() + mk.v[p].norm()
            })
            .reduce(|| 0.0, f64::max)
    }

    /// One explicit step of `dt` seconds. Errors: `dt` not positive or over the explicit
    /// limit ([`MpmError::TimeStep`]), a marker outside the grid ([`MpmError::OutOfBounds`]),
    /// a non-finite or degenerate marker state ([`MpmError::Diverged`]).
    pub fn step(&mut self, dt: f64) -> Result<()> {
        positive("dt", dt)?;
        let c = self.wave_speed();
        let limit = self.settings.cfl * self.spec.dx / c;
        if dt > limit {
            return Err(MpmError::TimeStep {
                field: "dt",
                value: dt,
                limit,
                cfl: self.settings.cfl,
                dx: self.spec.dx,
                wave_speed: c,
            });
        }
        self.advance(dt)
    }

    /// The step without the time-step check (`dt = 0` is a pure transfer P2G, G2P).
    pub(crate) fn advance(&mut self, dt: f64) -> Result<()> {
        self.check_bounds()?;
        for (k, r) in self.rigid.iter().enumerate() {
            r.check(k)?;
        }
        let mut t = Instant::now();
        self.p2g(dt);
        lap(&mut t, &mut self.timings.p2g);
        self.grid_update(dt);
        lap(&mut t, &mut self.timings.grid_update);
        self.g2p(dt)?;
        for r in &mut self.rigid {
            r.position += r.velocity * dt;
            r.last_dt = dt;
        }
        self.steps += 1;
        self.time += dt;
        Ok(())
    }

    fn check_bounds(&self) -> Result<()> {
        let (lo, hi) = self.spec.admissible();
        let bad = self
            .markers
            .x
            .par_iter()
            .with_min_len(MARKERS_PER_TASK)
            .position_first(|x| {
                !(0..3).all(|a| x[a] >= lo[a] && x[a] < hi[a]) // also catches NaN
            });
        match bad {
            None => Ok(()),
            Some(p) => {
                let x = self.markers.x[p];
                Err(MpmError::OutOfBounds {
                    marker: p,
                    x: x[0],
                    y: x[1],
                    z: x[2],
                    lo,
                    hi,
                    step: self.steps,
                })
            }
        }
    }

    /// Particle to grid: node masses and momenta (with the stress impulse of `dt`).
    pub(crate) fn p2g(&mut self, dt: f64) {
        let spec = self.spec;
        let mk = &self.markers;
        let n = mk.len();
        let origin = spec.origin;
        let dx = spec.dx;
        let shift = |st: &Stencil| {
            [
                (st.base[0] + GHOST) as usize,
                (st.base[1] + GHOST) as usize,
                (st.base[2] + GHOST) as usize,
            ]
        };
        let x = &mk.x;
        self.grid
            .rebuild(&spec, |p| shift(&Stencil::new(x[p].into(), origin, dx)), n);

        // Per-marker data in sorted order.
        let mat = self.material;
        let split = self.pressure.is_some();
        self.scratch.clear();
        self.scratch.resize(n, P2gMarker::default());
        let sorted = &self.grid.sorted;
        self.scratch
            .par_iter_mut()
            .with_min_len(MARKERS_PER_TASK)
            .enumerate()
            .for_each(|(s, d)| {
                let p = sorted[s].1 as usize;
                let st = Stencil::new(mk.x[p].into(), origin, dx);
                let m = mk.mass[p];
                // the split: the volumetric part is the pressure rows'
                let tau = mat.grid_stress(&mk.fe[p], &mk.fp[p], split);
                let a = tau * (-dt * mk.volume0[p]);
                let mc = mk.c[p] * m;
                *d = P2gMarker {
                    g0: shift(&st),
                    st,
                    m,
                    mv: (mk.v[p] * m).into(),
                    mc: rows(&mc),
                    a: rows(&a),
                };
            });

        // Gather per active block (the node arrays are taken out so the runs can be read
        // while the blocks are written; `take` does not allocate).
        let nb = spec.blocks();
        let mut mass = std::mem::take(&mut self.grid.mass);
        let mut mom = std::mem::take(&mut self.grid.mom);
        grid_gather(&self.grid, &self.scratch, nb, dx, &mut mass, &mut mom);
        if self.flip > 0.0 {
            let mut mom0 = std::mem::take(&mut self.grid.mom0);
            mom0.clear();
            mom0.resize(mom.len(), [0.0; 3]);
            transfer_gather(&self.grid, &self.scratch, nb, dx, &mut mom0);
            self.grid.mom0 = mom0;
        }
        self.grid.mass = mass;
        self.grid.mom = mom;
        self.p2g_mirrored(dt);
    }

    /// Total marker momentum `sum m_p v_p`, kg m/s (fixed-order sum).
    pub fn momentum(&self) -> Vector3<f64> {
        let mk = &self.markers;
        sum3(mk.len(), |p| mk.v[p] * mk.mass[p])
    }

    /// Total angular momentum about the origin, kg m^2/s, APIC's (Jiang et al. 2015,
    /// sec. 5.3): `sum_p x_p x m_p v_p + m_p (C_p D)^T : epsilon`, with `D = dx^2/4 I`;
    /// the second term is the spin the affine field carries.
    pub fn angular_momentum(&self) -> Vector3<f64> {
        let mk = &self.markers;
        let d = self.spec.dx * self.spec.dx / 4.0;
        sum3(mk.len(), |p| {
            let b = mk.c[p] * d; // B = C D
            let spin = Vector3::new(
                b[(2, 1)] - b[(1, 2)],
                b[(0, 2)] - b[(2, 0)],
                b[(1, 0)] - b[(0, 1)],
            );
            (mk.x[p].cross(&mk.v[p]) + spin) * mk.mass[p]
        })
    }

    /// Kinetic energy of the markers `sum m_p |v_p|^2 / 2`, J.
    pub fn kinetic_energy(&self) -> f64 {
        let mk = &self.markers;
        sum3(mk.len(), |p| {
            Vector3::new(0.5 * mk.mass[p] * mk.v[p].norm_squared(), 0.0, 0.0)
        })[0]
    }

    /// Elastic energy `sum V0_p Psi(F_E, F_P)`, J.
    pub fn elastic_energy(&self) -> f64 {
        let mk = &self.markers;
        let mat = &self.material;
        sum3(mk.len(), |p| {
            Vector3::new(
                mk.volume0[p] * mat.energy_density(&mk.fe[p], &mk.fp[p]),
                0.0,
                0.0,
            )
        })[0]
    }

    /// Node momentum (before the grid update) or velocity (after it) summed over the
    /// grid, weighted by node mass when `velocities`; for the transfer tests.
    #[cfg(test)]
    pub(crate) fn grid_totals(&self, velocities: bool) -> (Vector3<f64>, Vector3<f64>) {
        let nb = self.spec.blocks();
        let mut p = Vector3::zeros();
        let mut l = Vector3::zeros();
        for (k, &bk) in self.grid.active.iter().enumerate() {
            let b = unkey(bk, nb);
            for q in 0..BLOCK3 {
                let m = self.grid.mass[k * BLOCK3 + q];
                let loc = [q / (BLOCK * BLOCK), (q / BLOCK) % BLOCK, q % BLOCK];
                let xi = Vector3::from(std::array::from_fn::<f64, 3, _>(|a| {
                    self.spec.origin[a]
                        + ((b[a] * BLOCK + loc[a]) as f64 - GHOST as f64) * self.spec.dx
                }));
                let mut mv = Vector3::from(self.grid.mom[k * BLOCK3 + q]);
                if velocities {
                    mv *= m;
                }
                p += mv;
                l += xi.cross(&mv);
            }
        }
        (p, l)
    }
}

/// `v` after the wall conditions of the node at local index `l` of block `b`: those of
/// every domain face the node lies on.
#[inline]
fn apply_node_walls(v: &mut [f64; 3], b: [usize; 3], l: usize, spec: &GridSpec) {
    let loc = [l / (BLOCK * BLOCK), (l / BLOCK) % BLOCK, l % BLOCK];
    for a in 0..3 {
        let i = (b[a] * BLOCK + loc[a]) as i64 - GHOST;
        if i == 0 {
            apply_wall(v, a, 0, spec.walls[a][0]);
        } else if i == spec.cells[a] as i64 {
            apply_wall(v, a, 1, spec.walls[a][1]);
        }
    }
}

/// `v` after the wall condition of face `side` (0 lower, 1 upper) of axis `a`.
#[inline]
fn apply_wall(v: &mut [f64; 3], a: usize, side: usize, wall: Wall) {
    match wall {
        Wall::Open => {}
        Wall::Sticky => *v = [0.0; 3],
        Wall::Slip => v[a] = 0.0,
        Wall::Separating => {
            // Into the lower wall is v < 0, into the upper one v > 0.
            if (side == 0 && v[a] < 0.0) || (side == 1 && v[a] > 0.0) {
                v[a] = 0.0;
            }
        }
    }
}

fn rows(m: &Matrix3<f64>) -> [[f64; 3]; 3] {
    std::array::from_fn(|i| std::array::from_fn(|j| m[(i, j)]))
}

/// `sum_{p < n} f(p)` in a fixed order (chunks of chrono-core's reduction, in order).
fn sum3(n: usize, f: impl Fn(usize) -> Vector3<f64> + Sync) -> Vector3<f64> {
    use chrono_core::descriptor::reduce::{CHUNK, lane_sum};
    let chunks = n.div_ceil(CHUNK);
    let parts: Vec<[f64; 3]> = (0..chunks)
        .into_par_iter()
        .map(|c| {
            let (s, e) = (c * CHUNK, ((c + 1) * CHUNK).min(n));
            lane_sum::<3>(e - s, |j| f(s + j).into())
        })
        .collect();
    parts
        .iter()
        .fold(Vector3::zeros(), |acc, p| acc + Vector3::from(*p))
}

/// The P2G gather: each active block sums the markers of its 8 neighbouring marker blocks
/// (block offsets -1 and 0 per axis), in that fixed order and in the sorted marker order.
fn grid_gather(
    grid: &SparseGrid,
    scratch: &[P2gMarker],
    nb: [usize; 3],
    dx: f64,
    mass: &mut [f64],
    mom: &mut [[f64; 3]],
) {
    mass.par_chunks_mut(BLOCK3)
        .zip(mom.par_chunks_mut(BLOCK3))
        .with_min_len(BLOCKS_PER_TASK)
        .enumerate()
        .for_each(|(k, (mass, mom))| {
            mass.fill(0.0);
            mom.fill([0.0; 3]);
            let b = unkey(grid.active[k], nb);
            let lo = [b[0] * BLOCK, b[1] * BLOCK, b[2] * BLOCK];
            for run in grid.runs_reaching(b, nb) {
                for s in &scratch[run] {
                    scatter_into_block(s, lo, dx, mass, mom);
                }
            }
        });
}

/// The transfer's momentum alone (no stress impulse), gathered as [`grid_gather`] does.
fn transfer_gather(
    grid: &SparseGrid,
    scratch: &[P2gMarker],
    nb: [usize; 3],
    dx: f64,
    mom0: &mut [[f64; 3]],
) {
    mom0.par_chunks_mut(BLOCK3)
        .with_min_len(BLOCKS_PER_TASK)
        .enumerate()
        .for_each(|(k, mom)| {
            mom.fill([0.0; 3]);
            let b = unkey(grid.active[k], nb);
            let lo = [b[0] * BLOCK, b[1] * BLOCK, b[2] * BLOCK];
            for run in grid.runs_reaching(b, nb) {
                for s in &scratch[run] {
                    for_nodes_in_block(s, lo, |o, l| {
                        let w = s.st.weight(o);
                        let off = s.st.offset(o, dx);
                        for a in 0..3 {
                            let affine =
                                s.mc[a][0] * off[0] + s.mc[a][1] * off[1] + s.mc[a][2] * off[2];
                            mom[l][a] += w * (s.mv[a] + affine);
                        }
                    });
                }
            }
        });
}

/// Calls `f(o, l)` for each node of marker `s`'s stencil that lies in the block whose
/// first node is `lo` (`o`: the stencil offset, `l`: the node's index in the block), in
/// the stencil's order (the order that fixes the sums' bits).
#[inline]
fn for_nodes_in_block(s: &P2gMarker, lo: [usize; 3], mut f: impl FnMut([usize; 3], usize)) {
    let Some(r) = stencil_in_block(s.g0, lo) else {
        return;
    };
    for o0 in r[0].0..r[0].1 {
        for o1 in r[1].0..r[1].1 {
            for o2 in r[2].0..r[2].1 {
                let l = ((s.g0[0] + o0 - lo[0]) * BLOCK + (s.g0[1] + o1 - lo[1])) * BLOCK
                    + (s.g0[2] + o2 - lo[2]);
                f([o0, o1, o2], l);
            }
        }
    }
}

/// Adds one marker's contributions to the nodes of one block (those of its stencil that
/// lie in the block).
#[inline]
fn scatter_into_block(
    s: &P2gMarker,
    lo: [usize; 3],
    dx: f64,
    mass: &mut [f64],
    mom: &mut [[f64; 3]],
) {
    for_nodes_in_block(s, lo, |o, l| {
        let w = s.st.weight(o);
        let off = s.st.offset(o, dx);
        let gw = s.st.grad(o);
        mass[l] += w * s.m;
        for a in 0..3 {
            let affine = s.mc[a][0] * off[0] + s.mc[a][1] * off[1] + s.mc[a][2] * off[2];
            let force = s.a[a][0] * gw[0] + s.a[a][1] * gw[1] + s.a[a][2] * gw[2];
            mom[l][a] += w * (s.mv[a] + affine) + force;
        }
    });
}
