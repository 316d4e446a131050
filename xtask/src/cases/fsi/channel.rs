//! `fsi-channel`: the seed's scene "Interacting Rigid and Flexible Objects in Channel
//! Flow" — free ellipsoids and ANCF beams anchored to the floor in a WCSPH duct flow,
//! coupled two-way through BCE markers (chrono-fsi).
//!
//! Scene ([`chrono_fsi::channel`]): a duct `length x width x height`, periodic along the
//! flow (x), marker walls on the sides, the floor and the ceiling, no gravity (the bodies
//! are neutrally buoyant); the flow driven by the body force that gives the empty duct
//! the mean velocity `mean_velocity` (the laminar duct series, White 2006 eq. 3-49), the
//! fluid started on that profile; `ellipsoids` free ellipsoids placed at random without
//! overlap, `beams` ANCF beams clamped to the floor. The body force also pushes the solids
//! as the mean pressure gradient it stands for would.
//!
//! The seed (`--full`): 1.4 x 1 x 1 m, `rho` 1000, `mu` 1 Pa s, `U` 0.045 m/s (Re 45 on
//! the height), 2000 ellipsoids (2.25, 2.25, 3) cm (`Re_p` = U d / nu = 2.0), 40 beams
//! 1.5 cm x 64 cm, `E` 0.2 MPa, 4 elements (viscous Cauchy number `mu U l^3 / (E I)` =
//! 23.7): about 2.6e7 fluid particles at 4 spacings across a beam, far beyond this
//! machine. The default scales the scene: the seed's fluid, velocity and ellipsoids (so
//! `Re_p` holds), a 0.24 x 0.18 x 0.18 m channel (`Re` 8.1: the ratio `Re / Re_p` is the
//! channel's height over the ellipsoid's diameter), 4 ellipsoids, 2 beams 3 cm x 12 cm
//! (two thirds of the height, as the seed's) with `E` for the seed's Cauchy number.
//!
//! Checks (each a physical condition of a valid run, no tuned number):
//! - `fluid_inside`: the largest number, over every coupling step, of fluid particles that
//!   passed an ellipsoid's or a beam's outer marker layer (deeper than `dp / 2` below the
//!   surface): 0;
//! - `bodies_outside`: ellipsoids whose centre left the channel's cross-section: 0;
//! - `mach_warnings`: fluid sub-steps with the Mach number above chrono-sph's limit 0.1
//!   (the weakly compressible model's validity: density variation ~1 %): 0. A diverging
//!   run stops with the system's error before;
//! - `coupling_share` below 0.25 (the criterion): the coupling's share of the
//!   system step's wall time, `(T_step - T_fluid + T_markers) / T_step`: `T_step` the
//!   system steps, `T_fluid` the fluid's advance inside them
//!   (`SphFluid::advance_wall_time`), `T_markers` the markers' placement and force
//!   gathering at every fluid sub-step (`chrono_sph::Timings::markers`). So the share
//!   holds the marker work, the impulses' conversion to body and nodal loads, and the
//!   bodies' and beams' own step (collision, the CCP, the beams' implicit solve).
//!
//! Reported: `particle_reynolds` (mean over the bodies and the window of `|v_slip| d / nu`,
//! the slip against the fluid at the body's lateral position, `d` the equatorial
//! diameter) beside `particle_reynolds_nominal` (`U d / nu`), the beams' tip deflection
//! (horizontal, over the beams and the window: `tip_deflection_mean`, `_rms`, `_max`),
//! `particle_steps_per_s` (fluid particle-steps over the system steps' wall time),
//! `fluid_below_surface` (particles below a surface at all, within the outer layer), the
//! measured mean velocity and `reynolds`, `cauchy`, `solid_fraction`, sub-steps per step.
//!
//! With `--set active_supports=N` (an active domain of `N` kernel supports around the
//! ellipsoids and beams) the same scene also runs on the full domain, step by step in
//! turn, and the case reports the particles stepped (`active_stepped_fraction`), the
//! wall time saved (`active_wall_saving`), the largest distance between an ellipsoid's
//! positions in the two runs over the distance it travelled
//! (`active_trajectory_difference`) and the largest difference of a beam tip over the
//! largest tip displacement (`active_tip_difference`). Reported, not checked: the
//! channel's fluid is a through-flow, which an active domain freezes (see
//! docs/validation-fsi.md).

use chrono_core::descriptor::SolverSettings;
use chrono_fsi::channel::{ChannelParams, channel};
use serde::{Deserialize, Serialize};

use crate::case::{Case, CaseOutput, Check, Mode, PlotSpec, RunContext, Series};
use crate::params::{CaseParams, ParamCase, ParamInfo};

/// Parameters of `fsi-channel` (see [`ChannelParams`]).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct ChannelCaseParams {
    /// Channel length (the period along the flow), m.
    pub length: f64,
    /// Channel width, m.
    pub width: f64,
    /// Channel height, m.
    pub height: f64,
    /// Particle spacing, m.
    pub spacing: f64,
    /// Fluid density, kg/m^3.
    pub rho: f64,
    /// Dynamic viscosity, Pa s.
    pub viscosity: f64,
    /// Mean velocity of the empty duct, m/s.
    pub mean_velocity: f64,
    /// Number of ellipsoids.
    pub ellipsoids: usize,
    /// Ellipsoid semi-axis along body x, m.
    pub semi_axis_a: f64,
    /// Ellipsoid semi-axis along body y, m.
    pub semi_axis_b: f64,
    /// Ellipsoid semi-axis along body z, m.
    pub semi_axis_c: f64,
    /// Ellipsoid density, kg/m^3.
    pub body_density: f64,
    /// Number of beams.
    pub beams: usize,
    /// Beam diameter, m.
    pub beam_diameter: f64,
    /// Beam length, m.
    pub beam_length: f64,
    /// ANCF elements per beam.
    pub beam_elements: usize,
    /// Beam Young's modulus, Pa.
    pub young: f64,
    /// Beam density, kg/m^3.
    pub beam_density: f64,
    /// Simulated time, s.
    pub t_end: f64,
    /// Coupling (multibody) step, s.
    pub coupling_step: f64,
    /// Fraction of the run the statistics are taken over.
    pub window: f64,
    /// Placement seed.
    pub seed: u64,
    /// Active domain radius in kernel supports (0: off).
    pub active_supports: f64,
}

impl Default for ChannelCaseParams {
    fn default() -> Self {
        Self::from(&ChannelParams::default())
    }
}

impl From<&ChannelParams> for ChannelCaseParams {
    fn from(p: &ChannelParams) -> Self {
        Self {
            length: p.length,
            width: p.width,
            height: p.height,
            spacing: p.spacing,
            rho: p.rho,
            viscosity: p.viscosity,
            mean_velocity: p.mean_velocity,
            ellipsoids: p.ellipsoids,
            semi_axis_a: p.semi_axes[0],
            semi_axis_b: p.semi_axes[1],
            semi_axis_c: p.semi_axes[2],
            body_density: p.body_density,
            beams: p.beams,
            beam_diameter: p.beam_diameter,
            beam_length: p.beam_length,
            beam_elements: p.beam_elements,
            young: p.young,
            beam_density: p.beam_density,
            t_end: 0.5,
            coupling_step: p.coupling_step,
            window: 0.5,
            seed: p.seed,
            active_supports: p.active_supports.unwrap_or(0.0),
        }
    }
}

impl ChannelCaseParams {
    fn scene(&self) -> ChannelParams {
        ChannelParams {
            length: self.length,
            width: self.width,
            height: self.height,
            spacing: self.spacing,
            rho: self.rho,
            viscosity: self.viscosity,
            mean_velocity: self.mean_velocity,
            ellipsoids: self.ellipsoids,
            semi_axes: [self.semi_axis_a, self.semi_axis_b, self.semi_axis_c],
            body_density: self.body_density,
            beams: self.beams,
            beam_diameter: self.beam_diameter,
            beam_length: self.beam_length,
            beam_elements: self.beam_elements,
            young: self.young,
            beam_density: self.beam_density,
            coupling_step: self.coupling_step,
            seed: self.seed,
            active_supports: (self.active_supports > 0.0).then_some(self.active_supports),
            ..ChannelParams::default()
        }
    }
}

impl CaseParams for ChannelCaseParams {
    const INFO: &'static [ParamInfo] = &[
        ParamInfo::new("length", "m", "channel length along the flow (periodic)"),
        ParamInfo::new("width", "m", "channel width (side walls)"),
        ParamInfo::new("height", "m", "channel height (floor and ceiling)"),
        ParamInfo::new("spacing", "m", "particle spacing dp"),
        ParamInfo::new("rho", "kg/m^3", "fluid density"),
        ParamInfo::new("viscosity", "Pa s", "dynamic viscosity"),
        ParamInfo::new(
            "mean_velocity",
            "m/s",
            "mean velocity of the empty duct (sets the body force)",
        ),
        ParamInfo::new("ellipsoids", "-", "number of free ellipsoids"),
        ParamInfo::new("semi_axis_a", "m", "ellipsoid semi-axis, body x"),
        ParamInfo::new("semi_axis_b", "m", "ellipsoid semi-axis, body y"),
        ParamInfo::new("semi_axis_c", "m", "ellipsoid semi-axis, body z"),
        ParamInfo::new("body_density", "kg/m^3", "ellipsoid density"),
        ParamInfo::new("beams", "-", "number of beams clamped to the floor"),
        ParamInfo::new("beam_diameter", "m", "beam diameter (round section)"),
        ParamInfo::new("beam_length", "m", "beam length"),
        ParamInfo::new("beam_elements", "-", "ANCF elements per beam"),
        ParamInfo::new("young", "Pa", "beam Young's modulus"),
        ParamInfo::new("beam_density", "kg/m^3", "beam density"),
        ParamInfo::new("t_end", "s", "simulated time"),
        ParamInfo::new("coupling_step", "s", "multibody step h"),
        ParamInfo::new("window", "-", "fraction of the run the statistics cover"),
        ParamInfo::new("seed", "-", "seed of the ellipsoids' placement"),
        ParamInfo::new(
            "active_supports",
            "-",
            "active domain radius in kernel supports (0: off)",
        ),
    ];
    fn apply_mode(&mut self, mode: Mode) {
        match mode {
            Mode::Quick => self.t_end = 0.25,
            Mode::Default => {}
            Mode::Full => {
                let t = self.t_end;
                *self = Self::from(&ChannelParams::seed());
                self.t_end = t.max(2.0);
            }
        }
    }
}

fn run(p: &ChannelCaseParams, ctx: &RunContext) -> anyhow::Result<CaseOutput> {
    for (f, v) in [("t_end", p.t_end), ("coupling_step", p.coupling_step)] {
        anyhow::ensure!(
            v.is_finite() && v > 0.0,
            "parameter `{f}` must be finite and > 0, got {v}"
        );
    }
    anyhow::ensure!(
        p.window > 0.0 && p.window <= 1.0,
        "parameter `window` must be in (0, 1], got {}",
        p.window
    );
    let sp = p.scene();
    let solver = chrono_ccp::Psor::new(SolverSettings::default());
    let mut scene = channel(&sp, Box::new(solver))?;
    // with an active domain, the full-domain twin of the same scene, stepped in turn
    let mut twin = match sp.active_supports {
        Some(_) => {
            let full = ChannelParams {
                active_supports: None,
                ..sp.clone()
            };
            let solver = chrono_ccp::Psor::new(SolverSettings::default());
            Some(channel(&full, Box::new(solver))?)
        }
        None => None,
    };
    let mut travel = vec![0.0; scene.bodies.len()];
    let n = (p.t_end / p.coupling_step).round().max(1.0) as u64;
    let from = ((1.0 - p.window) * n as f64) as u64;
    let nu = sp.nu();
    let d = sp.equatorial_diameter();
    let (mut inside_max, mut below_max, mut outside_max) = (0usize, 0usize, 0usize);
    let (mut re_sum, mut re_n) = (0.0, 0usize);
    let (mut tip_sum, mut tip_sq, mut tip_max, mut tip_n) = (0.0, 0.0, 0.0f64, 0usize);
    let mut u_sum = 0.0;
    let mut series = Series::new([
        "t",
        "tip_deflection_max",
        "mean_velocity",
        "particle_reynolds",
    ]);
    for i in 1..=n {
        if let Some(t) = twin.as_mut() {
            t.step(p.coupling_step)?;
            for (d, &b) in travel.iter_mut().zip(&t.bodies) {
                *d += p.coupling_step * t.system.body(b)?.linear_velocity().norm();
            }
        }
        scene.step(p.coupling_step)?;
        inside_max = inside_max.max(scene.fluid_inside(0.5 * sp.spacing)?.total());
        below_max = below_max.max(scene.fluid_inside(0.0)?.total());
        outside_max = outside_max.max(scene.bodies_outside()?);
        let tips: Vec<f64> = (0..sp.beams)
            .filter_map(|k| scene.tip_displacement(k))
            .map(|t| t.x.hypot(t.y))
            .collect();
        let u = scene.mean_fluid_velocity();
        let mut re_step = f64::NAN;
        if i > from {
            for &t in &tips {
                tip_sum += t;
                tip_sq += t * t;
                tip_max = tip_max.max(t);
                tip_n += 1;
            }
            u_sum += u;
            // the slip is a pass over the fluid per body: every fifth step
            if (i - from) % 5 == 1 || i == n {
                let slips = scene.slip_velocities()?;
                let re: Vec<f64> = slips.iter().flatten().map(|s| s.norm() * d / nu).collect();
                if !re.is_empty() {
                    re_step = re.iter().sum::<f64>() / re.len() as f64;
                    re_sum += re.iter().sum::<f64>();
                    re_n += re.len();
                }
            }
        }
        if i % 2 == 0 || i == n {
            let tm = tips.iter().copied().fold(0.0, f64::max);
            series.push(&[scene.system.time(), tm, u, re_step]);
        }
        ctx.progress_steps(i, n);
    }
    let f = scene.fluid();
    let sph = f.sph();
    let step = scene.step_time;
    let markers = sph.timings().markers;
    let coupling = (step - f.advance_wall_time() + markers) / step;
    let windowed = (n - from) as f64;
    let mut out = CaseOutput::new();
    out.check(Check::below("fluid_inside", inside_max as f64, 0.0));
    out.check(Check::below("bodies_outside", outside_max as f64, 0.0));
    out.check(Check::below(
        "mach_warnings",
        sph.stats().mach_warnings as f64,
        0.0,
    ));
    out.check(Check::below("coupling_share", coupling, 0.25));
    let tip_n = tip_n.max(1) as f64;
    let u_mean = u_sum / windowed;
    out.metric(
        "particle_steps_per_s",
        sph.stats().fluid_steps as f64 / step,
    )
    .metric(
        "particle_reynolds",
        if re_n > 0 {
            re_sum / re_n as f64
        } else {
            f64::NAN
        },
    )
    .metric("particle_reynolds_nominal", sp.particle_reynolds())
    .metric("tip_deflection_mean", tip_sum / tip_n)
    .metric("tip_deflection_rms", (tip_sq / tip_n).sqrt())
    .metric("tip_deflection_max", tip_max)
    .metric("fluid_below_surface", below_max as f64)
    .metric("mean_velocity", u_mean)
    .metric("reynolds_nominal", sp.reynolds())
    .metric("reynolds", u_mean * sp.height / nu)
    .metric("cauchy", sp.cauchy())
    .metric("solid_fraction", sp.solid_fraction())
    .metric("body_force", scene.body_force)
    .metric("sound_speed", scene.sound_speed)
    .metric("fluid_particles", sph.num_fluid() as f64)
    .metric(
        "active_fraction",
        sph.stats().fluid_steps as f64 / (f.substeps() as f64 * sph.num_fluid() as f64),
    )
    .metric("substeps_per_step", f.substeps() as f64 / n as f64)
    .metric("step_wall_s", step)
    .metric("fluid_advance_s", f.advance_wall_time())
    .metric("marker_s", markers);
    if let Some(t) = &twin {
        let ft = t.fluid();
        let l = sp.length;
        let mut traj = 0.0f64;
        for ((&a, &b), d) in scene.bodies.iter().zip(&t.bodies).zip(&travel) {
            let (xa, xb) = (
                scene.system.body(a)?.position(),
                t.system.body(b)?.position(),
            );
            let mut r = xa - xb;
            r.x -= l * (r.x / l).round();
            traj = traj.max(r.norm() / d.max(f64::MIN_POSITIVE));
        }
        let (mut dtip, mut tip_full) = (0.0f64, 0.0f64);
        for k in 0..sp.beams {
            let (a, b) = (scene.tip_displacement(k), t.tip_displacement(k));
            if let (Some(a), Some(b)) = (a, b) {
                dtip = dtip.max((a - b).norm());
                tip_full = tip_full.max(b.norm());
            }
        }
        out.metric(
            "active_stepped_fraction",
            sph.stats().fluid_steps as f64 / ft.sph().stats().fluid_steps as f64,
        )
        .metric("active_wall_saving", 1.0 - step / t.step_time)
        .metric("full_step_wall_s", t.step_time)
        .metric("active_trajectory_difference", traj)
        .metric(
            "active_tip_difference",
            dtip / tip_full.max(f64::MIN_POSITIVE),
        );
    }
    out.series = series;
    out.plot = PlotSpec::new(
        "channel: largest beam tip deflection and mean fluid velocity",
        "t [s]",
        "m, m/s",
        &["tip_deflection_max", "mean_velocity"],
    );
    out.steps = f.substeps();
    Ok(out)
}

/// The `fsi-channel` case.
pub fn case() -> Box<dyn Case> {
    ParamCase::<ChannelCaseParams>::boxed(
        "fsi-channel",
        "fsi",
        "The seed's channel: free ellipsoids and ANCF beams clamped to the floor in a periodic WCSPH duct flow (BCE markers): no fluid inside a solid, no blow-up, no body leaving; particle Reynolds number, tip deflections, throughput and the coupling's share of the step.",
        run,
    )
}
