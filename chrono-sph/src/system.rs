//! [`SphSystem`]: the particles, the grid, the neighbour list and the time loop.
//!
//! One step (`dt` from the previous step's criteria) is a Stormer-Verlet
//! (kick-drift-kick) scheme in which the density is a *position-like* variable, updated
//! with the half-step velocity, so the acoustic pair (density, velocity) is integrated
//! symplectically (a scheme that kicks density and velocity alike with predicted values
//! is Heun-like and slowly unstable, with growth ~ (c dt / h)^4 per step):
//!
//! ```text
//! v^{n+1/2} = v^n + dt/2 a^n
//! x^{n+1}   = x^n + dt (v^{n+1/2} + Delta v_XSPH);   walls: x_w = x_w0 + X(t^{n+1}), v_w = X'(t^{n+1})
//! neighbours: if stale, grid build (re-sort by cell every `reorder_every` steps), CSR list
//! rho^{n+1} = rho^n + dt (d rho/dt)(x^{n+1}, v^{n+1/2}, p^n);  Delta v_XSPH(x^{n+1}, v^{n+1/2})
//!             (d rho/dt: continuity + delta-SPH diffusion, which reads p^n = Tait(rho^n))
//!             every `shepard_every` steps: Shepard filter of rho
//! p^{n+1}   = Tait(rho^{n+1});  wall markers: extrapolated p, rho, no-slip velocity
//! a^{n+1}   = a(x^{n+1}, rho^{n+1}, p^{n+1}, v^{n+1/2})
//! v^{n+1}   = v^{n+1/2} + dt/2 a^{n+1}
//! dt        = min(C_cfl h/(c_s + |v|max), C_f sqrt(h/|a|max), C_v h^2 rho_0/mu, max_dt)
//! ```
//!
//! One continuity pass and one force pass per step; the neighbour list (with a Verlet
//! skin) is rebuilt only when some particle moved more than half the skin.
//!
//! The step checks the state: a non-finite value stops with [`SphError::NonFinite`]
//! naming the particle id and step, a speed above `c_s` with [`SphError::Diverged`],
//! and a Mach number above [`SphSettings::mach_limit`] warns or stops
//! ([`MachPolicy`](crate::MachPolicy)). After the first steps the loop allocates nothing (checked by
//! `tests/no_alloc.rs`).

use std::time::Instant;

use chrono_core::particles::{CellGrid, GridConfig, Kernel, NeighborList};
use rayon::prelude::*;

use crate::carrier::{Carrier, NO_CARRIER, PointCarrier};
use crate::data::{FLUID, ParticleData, WALL};
use crate::distributed::{Refresh, Transport};
use crate::eos::Tait;
use crate::error::{Result, SphError};
use crate::interact::{self, PackVelocity, PassCtx};
use crate::motion::WallMotion;
use crate::pairs;
use crate::settings::{DensityDiffusion, SphSettings};

mod access;
pub mod active;
mod belts;
mod carriers;
mod checks;
pub mod halo;
mod neighbors;
mod open;

use active::{ACT_NOW, ALL, BUFFER};
use belts::belt_table;
pub(crate) use belts::belt_velocity;

/// Running statistics of the last step.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SphStats {
    /// Largest fluid speed, m/s.
    pub max_speed: f64,
    /// Largest fluid acceleration, m/s^2.
    pub max_acc: f64,
    /// Largest Mach number `|v| / c_s` seen so far.
    pub max_mach: f64,
    /// Steps in which the Mach number exceeded the limit.
    pub mach_warnings: u64,
    /// Directed entries of the last neighbour list (`sum_i |N(i)|`, skin included).
    pub neighbor_entries: usize,
    /// Neighbour-list builds so far.
    pub list_builds: u64,
    /// Fluid particles active (stepped) in the next step: all of them unless the active
    /// domain is on ([`SphSettings::active_domain`]).
    pub active_fluid: usize,
    /// Fluid particle-steps taken so far (the sum over steps of the particles stepped).
    pub fluid_steps: u64,
}

/// Accumulated wall time of the phases of [`SphSystem::step`], s.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Timings {
    /// Grid build, re-sort and CSR neighbour list.
    pub neighbor_search: f64,
    /// Density work: wall extrapolation, equation of state, Shepard filter.
    pub density: f64,
    /// The fluid interaction pass (continuity, momentum, XSPH fused).
    pub forces: f64,
    /// Kicks, drift, wall motion, checks and the time step.
    pub integration: f64,
    /// Marker carriers (coupled bodies and meshes): placing their markers at each step
    /// and gathering the fluid's force on them (counted here, not in `forces` or
    /// `integration`).
    pub markers: f64,
}

/// An explicit weakly compressible SPH system (see the [module docs](self)). Build one
/// with [`SphBuilder`](crate::SphBuilder).
#[derive(Debug)]
pub struct SphSystem {
    pub(crate) settings: SphSettings,
    pub(crate) kernel: Kernel,
    pub(crate) eos: Tait,
    pub(crate) motion: WallMotion,
    pub(crate) data: ParticleData,
    pub(crate) grid: CellGrid,
    pub(crate) list: NeighborList,
    bc: Vec<[f64; 5]>,
    /// The neighbour records of the last pass (see [`interact::Packed`]); after a step,
    /// those of the force pass.
    pub(crate) packed: Vec<interact::Packed>,
    /// Each fluid particle's in-support neighbours, recorded by the continuity pass for
    /// the force pass of the same step.
    support: pairs::Support,
    time: f64,
    steps: u64,
    dt: f64,
    initialized: bool,
    list_radius: f64,
    x_ref: Vec<[f64; 3]>,
    last_reorder: u64,
    stats: SphStats,
    timings: Timings,
    n_fluid: usize,
    /// Rigid marker carriers ([`crate::carrier`]).
    carriers: Vec<Carrier>,
    /// Point carriers ([`crate::carrier`]).
    point_carriers: Vec<PointCarrier>,
    /// Scratch: the fluid's force on each carrier marker, N.
    marker_f: Vec<[f64; 3]>,
    /// Scratch: the part of `marker_f` that a rigid co-rotation of the fluid with the
    /// marker's carrier would give (see `carrier_loads`), N.
    marker_g: Vec<[f64; 3]>,
    /// Active-domain flags of each particle ([`active`]; every flag when it is off).
    act: Vec<u8>,
    act_scratch: Vec<u8>,
    /// Whether each rigid / point carrier is a source of the active domain.
    carrier_source: Vec<bool>,
    point_source: Vec<bool>,
    /// The largest body-frame marker offset of each rigid carrier, m.
    carrier_radius: Vec<f64>,
    /// The sources' bounding spheres `[cx, cy, cz, r]` now and at the last list build.
    sources: Vec<[f64; 4]>,
    list_sources: Vec<[f64; 4]>,
    /// This rank's part of a decomposition ([`crate::distributed`]; `None`: the whole
    /// scene in this process).
    dist: Option<Box<halo::DistState>>,
    /// Scratch: the particle shifts of a step, m ([`crate::shifting`]).
    shift: Vec<[f64; 3]>,
    /// The force pass's concentration gradients for the shifting, 1/m (empty without
    /// shifting).
    shift_grad: Vec<[f64; 3]>,
    /// The belt velocity of each wall group ([`crate::WallBelt`], indexed by group; empty
    /// without belts), m/s.
    belts: Vec<[f64; 3]>,
    /// The angular velocity of each rigid carrier (world, rad/s) over the current
    /// interval, for the no-slip extrapolation of its markers.
    carrier_omega: Vec<[f64; 3]>,
    /// The open channel's inlet rows ([`crate::open`]; empty without one).
    inlet_rows: Vec<open::InletRow>,
    /// The next particle id to give (open channel).
    next_id: u32,
    /// Scratch: the particles kept by the open channel's outflow.
    keep: Vec<bool>,
}

impl SphSystem {
    pub(crate) fn new(
        settings: SphSettings,
        kernel: Kernel,
        eos: Tait,
        motion: WallMotion,
        data: ParticleData,
        carriers: Vec<Carrier>,
        point_carriers: Vec<PointCarrier>,
    ) -> Result<Self> {
        let h = settings.h();
        let mut lo = settings.domain_lower;
        let mut hi = settings.domain_upper;
        for a in 0..3 {
            if !settings.periodic[a] {
                lo[a] -= 2.0 * h;
                hi[a] += 2.0 * h;
            }
        }
        let radius = 2.0 * h * (1.0 + settings.skin);
        let grid =
            CellGrid::new(GridConfig::bounded(radius, lo, hi).with_periodic(settings.periodic))?;
        let n_fluid = data.kind.iter().filter(|&&k| k == FLUID).count();
        let n = data.len();
        let belts = belt_table(&settings, &data)?;
        let (nc, np) = (carriers.len(), point_carriers.len());
        let mut sys = Self {
            settings,
            kernel,
            eos,
            motion,
            data,
            grid,
            list: NeighborList::new(),
            bc: Vec::new(),
            packed: Vec::new(),
            support: pairs::Support::default(),
            time: 0.0,
            steps: 0,
            dt: 0.0,
            initialized: false,
            list_radius: radius,
            x_ref: Vec::new(),
            last_reorder: 0,
            stats: SphStats::default(),
            timings: Timings::default(),
            n_fluid,
            carriers,
            point_carriers,
            marker_f: Vec::new(),
            marker_g: Vec::new(),
            act: vec![ALL; n],
            act_scratch: Vec::new(),
            carrier_source: vec![true; nc],
            point_source: vec![true; np],
            carrier_radius: Vec::new(),
            sources: Vec::new(),
            list_sources: Vec::new(),
            dist: None,
            shift: Vec::new(),
            shift_grad: Vec::new(),
            belts,
            carrier_omega: Vec::new(),
            inlet_rows: Vec::new(),
            next_id: 0,
            keep: Vec::new(),
        };
        sys.carrier_radius = sys.carrier_radii();
        Ok(sys)
    }

    /// Places the wall markers at time `t` (prescribed motion), then the carriers'
    /// markers.
    fn move_walls(&mut self, t: f64) {
        self.move_tank_walls(t);
        if !self.carriers.is_empty() || !self.point_carriers.is_empty() {
            let t0 = Instant::now();
            self.move_carriers(t);
            self.timings.markers += t0.elapsed().as_secs_f64();
        }
    }

    /// Places the tank's wall markers at time `t` (prescribed [`WallMotion`]).
    fn move_tank_walls(&mut self, t: f64) {
        let k = self.motion.at(t);
        if matches!(self.motion, WallMotion::Fixed) && self.steps > 0 {
            return;
        }
        let belts = &self.belts;
        let d = &mut self.data;
        (
            d.x.par_iter_mut(),
            d.y.par_iter_mut(),
            d.z.par_iter_mut(),
            d.vx.par_iter_mut(),
            d.vy.par_iter_mut(),
            d.vz.par_iter_mut(),
            d.anchor.par_iter().zip(d.carrier.par_iter()),
            d.kind.par_iter().zip(d.group.par_iter()),
        )
            .into_par_iter()
            .for_each(|(x, y, z, vx, vy, vz, (a, &c), (&kind, &g))| {
                if kind == WALL && c == NO_CARRIER {
                    *x = a[0] + k.disp[0];
                    *y = a[1] + k.disp[1];
                    *z = a[2] + k.disp[2];
                    // a belt keeps its place and carries its tangential velocity (the
                    // continuity equation sees it)
                    let v = belt_velocity(belts, g, k.vel);
                    *vx = v[0];
                    *vy = v[1];
                    *vz = v[2];
                }
            });
    }

    /// Density work at the current positions: continuity (+ XSPH) with the current
    /// velocities and `rho += dt d rho/dt` (skipped when `dt = 0`), the Shepard filter
    /// when due, the equation of state and the wall extrapolation.
    #[cfg(test)]
    pub(crate) fn density_update(&mut self, dt: f64) {
        self.density_update_on(dt, None)
            .expect("no transport: nothing can fail");
    }

    /// [`density_update`](Self::density_update) with the ghosts refreshed from their
    /// owners after the density increment (and the Shepard filter) and after the wall
    /// extrapolation.
    fn density_update_on(
        &mut self,
        dt: f64,
        mut net: Option<&mut (dyn Transport + 'static)>,
    ) -> Result<()> {
        let t0 = Instant::now();
        let mut ctx = make_ctx(
            &self.settings,
            &self.kernel,
            &self.eos,
            &self.grid,
            &self.list,
            &self.motion,
            self.time,
            &self.belts,
            &self.carrier_omega,
        );
        let active = self.masked();
        if active {
            ctx.eval = Some(&self.act);
        }
        let mut deriv = std::mem::take(&mut self.data.deriv);
        interact::pack(&self.data, PackVelocity::Prescribed, &mut self.packed);
        pairs::continuity_pass(&self.packed, &ctx, &mut deriv, &mut self.support, true);
        self.data.deriv = deriv;
        if dt > 0.0 {
            let d = &mut self.data;
            let act = &self.act;
            // the particles that did the step's first half (A_n, see `active`)
            d.rho
                .par_iter_mut()
                .zip(d.deriv.par_iter())
                .zip(d.kind.par_iter())
                .enumerate()
                .for_each(|(i, ((rho, dv), &k))| {
                    if k == FLUID && act[i] & ACT_NOW != 0 {
                        *rho += dt * dv.drho;
                    }
                });
        }
        let every = self.settings.shepard_every as u64;
        let shepard = every > 0 && self.steps > 0 && self.steps.is_multiple_of(every);
        if let Some(t) = net.as_deref_mut() {
            // ctx borrows the grid and list only: the data are free
            Self::refresh(&mut self.dist, &mut self.data, Refresh::Density, t)?;
        }
        if shepard {
            let mut out = std::mem::take(&mut self.data.rho_half);
            interact::shepard(&mut self.data, &ctx, &mut out);
            self.data.rho_half = out;
            if let Some(t) = net.as_deref_mut() {
                Self::refresh(&mut self.dist, &mut self.data, Refresh::Density, t)?;
            }
        }
        interact::fluid_pressure(&mut self.data, &self.eos);
        Self::open_extrapolation(
            &self.settings,
            &self.kernel,
            &self.eos,
            &self.grid,
            &self.list,
            &self.act,
            &mut self.data,
            &mut self.bc,
            self.time,
        );
        // the records of the continuity pass: same positions, fluid velocities and kinds
        interact::wall_extrapolation(&mut self.data, &self.packed, &ctx, &mut self.bc);
        if let Some(t) = net {
            Self::refresh(&mut self.dist, &mut self.data, Refresh::Wall, t)?;
        }
        self.timings.density += t0.elapsed().as_secs_f64();
        Ok(())
    }

    /// The force pass at the current state.
    fn force_update(&mut self) {
        let t0 = Instant::now();
        let mut ctx = make_ctx(
            &self.settings,
            &self.kernel,
            &self.eos,
            &self.grid,
            &self.list,
            &self.motion,
            self.time,
            &self.belts,
            &self.carrier_omega,
        );
        if self.masked() {
            ctx.eval = Some(&self.act);
        }
        let mut deriv = std::mem::take(&mut self.data.deriv);
        let mut grad = std::mem::take(&mut self.shift_grad);
        if self.settings.shifting.is_some() {
            grad.resize(deriv.len(), [0.0; 3]);
        } else {
            grad.clear();
        }
        interact::pack(&self.data, PackVelocity::NoSlip, &mut self.packed);
        // the positions are those of the continuity pass: its kept neighbours hold
        pairs::force_pass(
            &self.packed,
            &ctx,
            &mut deriv,
            &mut grad,
            &mut self.support,
            true,
        );
        self.data.deriv = deriv;
        self.shift_grad = grad;
        self.timings.forces += t0.elapsed().as_secs_f64();
    }

    /// Sets the velocity damping rate (1/s, see [`SphSettings::damping`]); 0 turns it
    /// off. For relaxing a lattice start before the measured run.
    pub fn set_damping(&mut self, rate: f64) -> Result<()> {
        crate::error::non_negative("damping", rate)?;
        self.settings.damping = rate;
        Ok(())
    }

    /// Half kick `v += dt/2 a` of the fluid (then `v *= exp(-k dt/2)` with damping).
    fn kick(&mut self, half: f64) {
        let damp = (-self.settings.damping * half).exp();
        let d = &mut self.data;
        (
            d.vx.par_iter_mut(),
            d.vy.par_iter_mut(),
            d.vz.par_iter_mut(),
            d.deriv.par_iter(),
            d.kind.par_iter(),
            self.act.par_iter(),
        )
            .into_par_iter()
            .for_each(|(vx, vy, vz, dv, &kind, &act)| {
                if kind == FLUID && act & ACT_NOW != 0 {
                    *vx = (*vx + half * dv.acc[0]) * damp;
                    *vy = (*vy + half * dv.acc[1]) * damp;
                    *vz = (*vz + half * dv.acc[2]) * damp;
                }
            });
    }

    /// Evaluates the state at the current time without advancing it (walls placed,
    /// neighbour list, pressures, wall extrapolation, density rates, accelerations and
    /// the next `dt`), so [`ParticleData::deriv`](crate::ParticleData::deriv) can be
    /// inspected; [`step`](Self::step) calls it once, and later calls do nothing.
    pub fn initialize(&mut self) -> Result<()> {
        self.initialize_on(None)
    }

    /// [`initialize`](Self::initialize) of a distributed system (or of a whole one with
    /// `None`).
    pub fn initialize_on(&mut self, mut net: Option<&mut (dyn Transport + 'static)>) -> Result<()> {
        self.check_net(&net)?;
        if self.initialized {
            return Ok(());
        }
        self.check_active_domain()?;
        self.init_open_channel();
        self.move_walls(self.time);
        self.update_activity();
        self.set_inflow();
        self.stats.active_fluid = self.promote_activity();
        self.neighbor_search(net.as_deref_mut())?;
        // the density diffusion reads the pressures of the initial densities
        interact::fluid_pressure(&mut self.data, &self.eos);
        self.density_update_on(0.0, net.as_deref_mut())?;
        self.force_update();
        self.carrier_loads();
        self.check_and_set_dt(net)?;
        self.stats.active_fluid = self.promote_activity();
        if self.dist.is_some() {
            // a rebuild at the first step: the cuts move to the work measured by this
            // evaluation's list (see `crate::distributed`)
            self.x_ref.clear();
        }
        self.initialized = true;
        Ok(())
    }

    /// Advances one time step; returns the step size taken, s.
    pub fn step(&mut self) -> Result<f64> {
        self.initialize()?;
        let dt = self.dt;
        self.step_by(dt, None, None)?;
        Ok(dt)
    }

    /// Advances one time step of this rank's part of a distributed system
    /// ([`distribute`](Self::distribute)); every rank calls it with its transport, and
    /// all take the same step size (returned, s).
    pub fn step_on(&mut self, net: &mut (dyn Transport + 'static)) -> Result<f64> {
        self.initialize_on(Some(&mut *net))?;
        let dt = self.dt;
        self.step_by(dt, None, Some(net))?;
        Ok(dt)
    }

    /// Advances to `t_end` (s) exactly: as many steps as the stability criteria need (CFL,
    /// force, viscous: [`dt`](Self::dt)), the last one shortened to end at `t_end`; when the
    /// rest is between one and two steps it is split in two equal steps (no sliver step).
    /// Returns the number of steps taken. The rigid carriers' markers move at every step
    /// ([`set_carrier_motion`](Self::set_carrier_motion)). `t_end` before the current time
    /// is an error.
    pub fn advance_exactly(&mut self, t_end: f64) -> Result<u64> {
        if !(t_end.is_finite() && t_end >= self.time) {
            return Err(SphError::invalid(
                "t_end",
                t_end,
                format!("must be finite and >= the current time {} s", self.time),
            ));
        }
        self.initialize()?;
        let mut n = 0;
        while self.time < t_end {
            let rest = t_end - self.time;
            let dt = self.dt;
            if dt >= rest {
                self.step_by(rest, Some(t_end), None)?;
            } else if 2.0 * dt > rest {
                self.step_by(0.5 * rest, None, None)?;
            } else {
                self.step_by(dt, None, None)?;
            }
            n += 1;
        }
        Ok(n)
    }

    /// One kick-drift-kick step of size `dt`; the clock ends at `t_new` if given (the
    /// last step of [`advance_exactly`](Self::advance_exactly)), else at `time + dt`.
    fn step_by(
        &mut self,
        dt: f64,
        t_new: Option<f64>,
        mut net: Option<&mut (dyn Transport + 'static)>,
    ) -> Result<()> {
        self.check_net(&net)?;
        if self.settings.shifting.is_some() && net.is_some() {
            return Err(SphError::invalid(
                "settings.shifting",
                "on",
                "particle shifting does not run over ranks yet",
            ));
        }
        let t0 = Instant::now();
        let half = 0.5 * dt;
        let (lo, hi, per) = (
            self.settings.domain_lower,
            self.settings.domain_upper,
            self.settings.periodic,
        );
        let wrap = move |v: &mut f64, a: usize| {
            if per[a] {
                let l = hi[a] - lo[a];
                *v = lo[a] + (*v - lo[a]).rem_euclid(l);
            }
        };
        self.kick(half);
        self.kick_carriers(half);
        {
            let d = &mut self.data;
            (
                d.x.par_iter_mut(),
                d.y.par_iter_mut(),
                d.z.par_iter_mut(),
                d.vx.par_iter(),
                d.vy.par_iter(),
                d.vz.par_iter(),
                (d.deriv.par_iter(), d.kind.par_iter()),
                self.act.par_iter(),
            )
                .into_par_iter()
                .for_each(|(x, y, z, vx, vy, vz, (dv, &kind), &act)| {
                    if kind != FLUID {
                        return;
                    }
                    if act & ACT_NOW != 0 {
                        *x += dt * (vx + dv.xsph[0]);
                        *y += dt * (vy + dv.xsph[1]);
                        *z += dt * (vz + dv.xsph[2]);
                    } else if act & BUFFER != 0 {
                        // an open channel's buffer particle moves with its imposed velocity
                        *x += dt * vx;
                        *y += dt * vy;
                        *z += dt * vz;
                    } else {
                        return;
                    }
                    wrap(x, 0);
                    wrap(y, 1);
                    wrap(z, 2);
                });
        }
        self.advance_inlet_rows(dt);
        self.time = t_new.unwrap_or(self.time + dt);
        self.steps += 1;
        self.move_walls(self.time);
        self.update_activity();
        self.set_inflow();
        if let Some(t) = net.as_deref_mut() {
            Self::refresh(&mut self.dist, &mut self.data, Refresh::Kinematic, t)?;
        }
        self.timings.integration += t0.elapsed().as_secs_f64();
        self.neighbor_search(net.as_deref_mut())?;
        self.density_update_on(dt, net.as_deref_mut())?;
        self.force_update();
        self.carrier_loads();
        let t1 = Instant::now();
        self.kick(half);
        self.kick_carriers(half);
        if let Some(sh) = self.settings.shifting {
            self.shift_particles(sh, dt, wrap);
        }
        self.stats.fluid_steps += self.stats.active_fluid as u64;
        self.stats.active_fluid = self.promote_activity();
        self.check_and_set_dt(net)?;
        self.timings.integration += t1.elapsed().as_secs_f64();
        Ok(())
    }

    /// Moves the stepped fluid particles by their shifts ([`crate::shifting`]) at the
    /// end of a step of length `dt`; `wrap` maps a coordinate back into a periodic axis.
    fn shift_particles(
        &mut self,
        shifting: crate::Shifting,
        dt: f64,
        wrap: impl Fn(&mut f64, usize) + Sync,
    ) {
        let mut out = std::mem::take(&mut self.shift);
        let eval = self.masked().then_some(&self.act[..]);
        crate::shifting::shifts(
            &self.data,
            eval,
            shifting,
            self.kernel.h(),
            dt,
            &self.shift_grad,
            &mut out,
        );
        let d = &mut self.data;
        (
            d.x.par_iter_mut(),
            d.y.par_iter_mut(),
            d.z.par_iter_mut(),
            out.par_iter(),
        )
            .into_par_iter()
            .for_each(|(x, y, z, s)| {
                // walls and frozen particles have no shift: leave their bits alone
                if *s == [0.0; 3] {
                    return;
                }
                *x += s[0];
                *y += s[1];
                *z += s[2];
                wrap(x, 0);
                wrap(y, 1);
                wrap(z, 2);
            });
        self.shift = out;
    }

    /// The pass context for the current time (probes and filters).
    pub(crate) fn pass_ctx(&self) -> PassCtx<'_> {
        make_ctx(
            &self.settings,
            &self.kernel,
            &self.eos,
            &self.grid,
            &self.list,
            &self.motion,
            self.time,
            &self.belts,
            &self.carrier_omega,
        )
    }

    /// Advances until `time() >= t_end` (the last step is not shortened, see
    /// [`advance_exactly`](Self::advance_exactly) for one that is); returns the number of
    /// steps taken.
    pub fn advance_to(&mut self, t_end: f64) -> Result<u64> {
        let mut n = 0;
        while self.time < t_end - 1e-12 {
            self.step()?;
            n += 1;
        }
        Ok(n)
    }
}

/// The pass context from the system's parts (split borrows: `data` stays free).
#[allow(clippy::too_many_arguments)]
fn make_ctx<'a>(
    s: &SphSettings,
    kernel: &'a Kernel,
    eos: &'a Tait,
    grid: &'a CellGrid,
    list: &'a NeighborList,
    motion: &WallMotion,
    time: f64,
    belts: &'a [[f64; 3]],
    carrier_omega: &'a [[f64; 3]],
) -> PassCtx<'a> {
    let kin = motion.at(time);
    PassCtx {
        kernel,
        eos,
        grid,
        periodic: s.periodic.iter().any(|&p| p),
        list,
        mu: s.viscosity,
        alpha: s.artificial_viscosity,
        xsph: s.xsph,
        accel: [
            s.gravity[0] + s.body_force[0],
            s.gravity[1] + s.body_force[1],
            s.gravity[2] + s.body_force[2],
        ],
        gravity: s.gravity,
        wall_acc: kin.acc,
        wall_vel: kin.vel,
        clamp_wall_pressure: s.clamp_wall_pressure,
        wall_volume: s.spacing * s.spacing * s.spacing,
        diffusion: s.density_diffusion,
        diffusion_coef: if s.density_diffusion == DensityDiffusion::None {
            0.0
        } else {
            2.0 * s.diffusion_delta * kernel.h() * s.sound_speed
        },
        inv_c2: 1.0 / (s.sound_speed * s.sound_speed),
        no_slip: s.no_slip,
        eval: None,
        shift: match s.shifting {
            None => 0,
            Some(sh) if sh.form == crate::ShiftForm::LocalSpeed => 1,
            Some(_) => 2,
        },
        inv_w_dp: 1.0 / kernel.w(s.spacing),
        belts,
        carrier_omega,
    }
}
