//! `hmmwv-granular`: the speed controller holds 2 m/s on a moving granular patch.
//!
//! `tire = ancf` mounts the pressurized ANCF shell tires (NSC only); it adds the check
//! `grains_inside_tires` = 0 (no grain centre ever on the inner side of a carcass, counted
//! every 50 steps; the carcass touches the grains with its element faces).
//!
//! A bed of spherical grains (`chrono_vehicle::terrain::GranularPatch`) settles in a box
//! under the vehicle; the HMMWV (rigid tires; the suspension joints and the driveline
//! shafts are CCP rows solved by the Schur solver) drives `distance` m straight ahead while
//! the patch moves with it, rear slab to front. Checks: the mean forward speed after the
//! first second within 10 % of the target; the vehicle covered `distance` with the grain
//! count fixed (the patch's count, reported as `grains`). Metrics: `sinkage` (bed surface
//! minus the lowest point of the tires, averaged over the wheels and the second half of
//! the run), wall time.
//!
//! Three things a vehicle on loose spheres needs, each a parameter (runs in
//! `docs/validation-vehicle.md`):
//! - rolling resistance of the grains (`rolling_friction`, 0.2): without it the spheres
//!   roll like ball bearings under a driven wheel and the vehicle crawls at full throttle;
//! - locked differentials (`diff_lock_torque`): with open ones the torque goes to the
//!   wheel with the least grip, which spins at 15-20 m/s while the vehicle stands;
//! - traction control (`max_slip`): at full throttle the locked wheels spin at 95 % slip
//!   and dig in; the driver cuts the throttle in proportion to the slip above `max_slip`.
//!
//! With SMC contact the time step must resolve the grain contacts: `h = 2.5e-4` s for the
//! 8 cm grains (`5e-4` diverged, see the docs).
//!
//! Grain contact is SMC by default (`method`): NSC grains under the loaded wheels need
//! 300-700 APGD iterations per step to converge (a heavy-on-light stack; at 60 the
//! unconverged impulses throw the vehicle off), about 7 steps/s for the quick bed.
//!
//! The vehicle rests braked on the bed for `vehicle_settle`, then starts rolling at
//! `initial_speed` (`WheeledVehicle::set_forward_speed`), so the landing is not part of
//! the measured run.

use std::time::Instant;

use chrono_core::math::Isometry3;
use chrono_core::{System, SystemSettings};
use chrono_vehicle::driver::{PidGains, SpeedController, TractionControl};
use chrono_vehicle::hmmwv::{TireKind, hmmwv_data_with};
use chrono_vehicle::scene::{
    front_reach, lock_differentials, mean_sinkage, mean_wheel_surface_speed, start_height,
};
use chrono_vehicle::terrain::{FlatTerrain, GranularPatch, GranularPatchParams};
use chrono_vehicle::{DriverInputs, WheeledVehicle};
use serde::{Deserialize, Serialize};

use crate::case::{Case, CaseOutput, Check, Mode, PlotSpec, RunContext, Series};
use crate::cases::rigid::{VtkFrames, make_solver, n_steps};
use crate::params::{CaseParams, ParamCase, ParamInfo};

/// Parameters of `hmmwv-granular`.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct GranularParams {
    /// Grain diameter, m.
    pub grain_diameter: f64,
    /// Grain friction coefficient (grains, walls and tires).
    pub mu: f64,
    /// Grain density, kg/m^3.
    pub grain_density: f64,
    /// Young's modulus of the grains (SMC Hertz contact; NSC ignores it), Pa.
    pub grain_young_modulus: f64,
    /// Young's modulus of the rigid tires' tread for SMC contact, Pa (`RigidTire::
    /// young_modulus`); 0 = the grains' (a tire softer than the grains would carry the
    /// contact's compliance itself). The data's value is 2e7 Pa, the grains' default.
    pub tire_young_modulus: f64,
    /// Patch length (X), m.
    pub patch_length: f64,
    /// Patch width (Y), m.
    pub patch_width: f64,
    /// Bed depth before settling, m.
    pub depth: f64,
    /// Width of the two lanes of grains under the wheel tracks, m (`GranularPatchParams::
    /// lanes`, centred on the wheels); 0 = one bed of `patch_width`. A bed of small grains
    /// then costs only the ground the tires reach.
    pub lane_width: f64,
    /// Distance to drive, m.
    pub distance: f64,
    /// Target speed, m/s.
    pub speed: f64,
    /// Speed the vehicle starts at (rolling, shafts at their geared speeds), m/s: the
    /// controller holds the target from the start, as in a vehicle test.
    pub initial_speed: f64,
    /// Proportional gain of the speed controller (pedal per m/s).
    pub speed_kp: f64,
    /// Integral gain of the speed controller (pedal per m).
    pub speed_ki: f64,
    /// Time step, s.
    pub h: f64,
    /// Settling time of the bed before the vehicle is set down, s.
    pub settle: f64,
    /// Time the vehicle rests on the bed, braked, before it starts rolling, s.
    pub vehicle_settle: f64,
    /// Height of the tires' lowest points above the bed's surface when the vehicle is set
    /// down, m (the landing's drop).
    pub drop_height: f64,
    /// Contact method of the grains and tires: `nsc` or `smc` (penalty; the joints and
    /// shafts stay rows of the CCP). SMC needs `h` below the contact-duration limit the
    /// system checks (about 1.2 ms for the quick grains).
    pub method: chrono_core::ContactMethod,
    /// Rolling friction coefficient of the grains.
    pub rolling_friction: f64,
    /// Rolling resistance model (`chrono_core::contact::smc::RollingModel`): `relative`
    /// (Ai et al.'s type A with a limiter), `per_body` or `spring` (type C, an
    /// elastic-plastic spring that holds a static moment; SMC only, NSC's rolling rows act
    /// as `relative`).
    pub rolling_model: chrono_core::contact::smc::RollingModel,
    /// NSC only: 0 = the relaxed cone (one solve a step; a sliding or rolling contact
    /// separates at `mu |u_t| + mu_r |u_r|`); `n` > 0 = Coulomb's law by up to `n`
    /// de Saxcé passes (`chrono_core::FrictionLaw::Coulomb`).
    pub coulomb_passes: usize,
    /// Largest wheel slip `s = (w R - v) / (w R)` the driver's traction control allows
    /// (the throttle is cut in proportion to the excess: `throttle *= 1 - 5 (s - s_max)`,
    /// clamped to [0, 1]); 0 = no traction control.
    pub max_slip: f64,
    /// Torque the differential locks hold, N m; 0 = the data's open differentials. The
    /// driver engages the three locks for loose ground (see the module documentation).
    pub diff_lock_torque: f64,
    /// Normal compliance of the grain contacts, m/N (NSC; 0 = rigid).
    pub compliance: f64,
    /// Solver tolerance (m/s) and iteration cap.
    pub tolerance: f64,
    /// Iteration cap of the solver.
    pub max_iterations: usize,
    /// CCP solver by name (`chrono_ccp::SOLVER_NAMES`): `schur` (joints by direct
    /// elimination, contacts by APGD) or `local-direct` (the rows around the heavy bodies
    /// by ADMM, the rest by APGD: the NSC heavy-on-light path).
    pub solver: String,
    /// `local-direct` only: contact hops around the heavy bodies in the direct block
    /// (`chrono_ccp::LocalDirectOptions::hops`).
    pub local_hops: usize,
    /// `local-direct` only: the far block's solver, `apgd` or `apsor`
    /// (`chrono_ccp::LocalDirectOptions::far_solver`).
    pub far_solver: String,
    /// Solves (counted from 0, the bed's settling included) whose problem and warm start
    /// are saved to the case's output directory as `capture_n.ccpb` / `capture_n.warm`
    /// (`chrono_ccp::Capture`; replay with `chrono-ccp`'s example `replay_step`).
    pub capture: Vec<usize>,
    /// Tire model: `rigid` (cylinders) or `ancf` (the pressurized shell carcass; NSC only:
    /// the SMC stepper does not take items' collision proxies).
    pub tire: TireKind,
    /// Stiffness-proportional damping `beta` of the ANCF tire's carcass, s (negative = the
    /// data's).
    pub tire_damping: f64,
}

impl Default for GranularParams {
    fn default() -> Self {
        Self {
            grain_diameter: 0.08,
            mu: 0.8,
            grain_density: 2500.0,
            grain_young_modulus: 2e7,
            tire_young_modulus: 0.0,
            patch_length: 7.0,
            patch_width: 2.6,
            depth: 0.24,
            lane_width: 0.0,
            distance: 20.0,
            speed: 2.0,
            initial_speed: 2.0,
            speed_kp: 1.0,
            speed_ki: 0.5,
            h: 2.5e-4,
            settle: 0.6,
            vehicle_settle: 0.3,
            drop_height: 0.01,
            method: chrono_core::ContactMethod::Smc,
            rolling_friction: 0.2,
            rolling_model: chrono_core::contact::smc::RollingModel::Relative,
            coulomb_passes: 0,
            diff_lock_torque: 3e4,
            max_slip: 0.4,
            compliance: 0.0,
            tolerance: 1e-3,
            max_iterations: 60,
            solver: "schur".into(),
            local_hops: chrono_ccp::LocalDirectOptions::default().hops,
            far_solver: "apgd".into(),
            capture: Vec::new(),
            tire: TireKind::Rigid,
            tire_damping: -1.0,
        }
    }
}

impl CaseParams for GranularParams {
    const INFO: &'static [ParamInfo] = &[
        ParamInfo::new("grain_diameter", "m", "grain diameter"),
        ParamInfo::new("mu", "-", "friction coefficient of grains, walls and tires"),
        ParamInfo::new("grain_density", "kg/m^3", "grain density"),
        ParamInfo::new(
            "grain_young_modulus",
            "Pa",
            "grain Young's modulus (SMC Hertz contact)",
        ),
        ParamInfo::new(
            "tire_young_modulus",
            "Pa",
            "rigid tires' tread Young's modulus (SMC; 0 = the grains')",
        ),
        ParamInfo::new("patch_length", "m", "length of the moving patch"),
        ParamInfo::new("patch_width", "m", "width of the patch"),
        ParamInfo::new("depth", "m", "bed depth before settling"),
        ParamInfo::new(
            "lane_width",
            "m",
            "width of a lane of grains under each wheel track (0 = one bed of patch_width)",
        ),
        ParamInfo::new("distance", "m", "distance to drive"),
        ParamInfo::new("speed", "m/s", "target speed of the speed controller"),
        ParamInfo::new("initial_speed", "m/s", "speed the vehicle starts at"),
        ParamInfo::new(
            "speed_kp",
            "1/(m/s)",
            "proportional gain of the speed controller",
        ),
        ParamInfo::new("speed_ki", "1/m", "integral gain of the speed controller"),
        ParamInfo::new("h", "s", "time step"),
        ParamInfo::new("settle", "s", "settling time of the bed"),
        ParamInfo::new(
            "vehicle_settle",
            "s",
            "time the braked vehicle rests on the bed before it rolls",
        ),
        ParamInfo::new(
            "drop_height",
            "m",
            "height of the tires above the bed when the vehicle is set down",
        ),
        ParamInfo::new("method", "-", "grain contact method: nsc | smc"),
        ParamInfo::new(
            "rolling_friction",
            "-",
            "rolling friction coefficient of the grains",
        ),
        ParamInfo::new(
            "rolling_model",
            "-",
            "rolling resistance model: relative | per_body | spring (SMC)",
        ),
        ParamInfo::new(
            "coulomb_passes",
            "-",
            "NSC: de Saxce passes of Coulomb's law per step (0 = the relaxed cone)",
        ),
        ParamInfo::new(
            "max_slip",
            "-",
            "largest wheel slip of the traction control (0 = none)",
        ),
        ParamInfo::new(
            "diff_lock_torque",
            "N m",
            "torque of the engaged differential locks (0 = open differentials)",
        ),
        ParamInfo::new(
            "compliance",
            "m/N",
            "normal compliance of the grain contacts (NSC)",
        ),
        ParamInfo::new("tolerance", "m/s", "solver tolerance"),
        ParamInfo::new("max_iterations", "-", "solver iteration cap"),
        ParamInfo::new(
            "solver",
            "-",
            "CCP solver: schur | local-direct | any of chrono_ccp::SOLVER_NAMES",
        ),
        ParamInfo::new(
            "local_hops",
            "-",
            "local-direct: contact hops around the heavy bodies solved directly",
        ),
        ParamInfo::new(
            "far_solver",
            "-",
            "local-direct: the far block's solver, apgd | apsor",
        ),
        ParamInfo::new(
            "capture",
            "-",
            "solves whose problem and warm start are saved (capture_n.* in the output directory)",
        ),
        ParamInfo::new(
            "tire",
            "-",
            "tire model: rigid | ancf (ancf needs method = nsc)",
        ),
        ParamInfo::new(
            "tire_damping",
            "s",
            "ANCF tire's stiffness damping beta (negative: the data's)",
        ),
    ];
    fn apply_mode(&mut self, mode: Mode) {
        // The default run drives the quick course too (~120 s), for its 20-minute budget
        // (`xtask/src/budget.rs`); `--full` keeps the 20 m run on the 7 m patch (~400 s).
        if mode != Mode::Full {
            self.patch_length = 6.0;
            // 6 m, not 4: the first ~2 s are the speed controller winding up after the
            // rolling start (engine braking at zero throttle since the reverse-flow
            // converter), which a 4 m run averages as -11 %.
            self.distance = 6.0;
            self.settle = 0.4;
        }
    }
}

fn run(p: &GranularParams, ctx: &RunContext) -> anyhow::Result<CaseOutput> {
    let method = p.method;
    anyhow::ensure!(
        p.distance > 0.0 && p.speed > 0.0,
        "parameters `distance` and `speed` must be > 0"
    );
    for (name, value) in [
        ("max_slip", p.max_slip),
        ("diff_lock_torque", p.diff_lock_torque),
        ("vehicle_settle", p.vehicle_settle),
        ("drop_height", p.drop_height),
        ("tire_young_modulus", p.tire_young_modulus),
    ] {
        anyhow::ensure!(
            value.is_finite() && value >= 0.0,
            "parameter `{name}` must be finite and >= 0, got {value}"
        );
    }
    let sys_settings = SystemSettings {
        contact_method: method,
        rolling_model: p.rolling_model,
        friction_law: if p.coulomb_passes > 0 {
            chrono_core::FrictionLaw::Coulomb {
                passes: p.coulomb_passes,
            }
        } else {
            chrono_core::FrictionLaw::Relaxed
        },
        ..SystemSettings::default()
    };
    let mut solver = make_solver(&p.solver, p.tolerance, p.max_iterations)?;
    if p.solver == "local-direct" {
        let far_solver = chrono_ccp::FarSolver::from_name(&p.far_solver).ok_or_else(|| {
            anyhow::anyhow!(
                "parameter `far_solver` = {}: expected apgd or apsor",
                p.far_solver
            )
        })?;
        let options = chrono_ccp::LocalDirectOptions {
            hops: p.local_hops,
            far_solver,
            ..chrono_ccp::LocalDirectOptions::default()
        };
        solver =
            Box::new(chrono_ccp::LocalDirect::new(solver.settings().clone()).with_options(options));
    }
    if !p.capture.is_empty() {
        let prefix = ctx.out_dir.join("capture");
        solver = Box::new(
            chrono_ccp::Capture::new(solver, &p.capture, &prefix)
                .map_err(|e| anyhow::anyhow!("parameter `capture`: {}: {e}", prefix.display()))?,
        );
    }
    let mut sys = System::new(sys_settings, solver)?;
    anyhow::ensure!(
        p.tire != TireKind::Handling,
        "parameter `tire` = handling: the handling tire reads a height map, not grains (use rigid or ancf)"
    );
    anyhow::ensure!(
        !(p.tire == TireKind::Ancf && method == chrono_core::ContactMethod::Smc),
        "parameter `tire` = ancf needs `method` = nsc: the SMC stepper does not take the carcass' node spheres"
    );
    let mut data = hmmwv_data_with(p.tire)?;
    if let chrono_vehicle::tire::Tire::Rigid(t) = &mut data.wheel.tire {
        t.young_modulus = if p.tire_young_modulus > 0.0 {
            p.tire_young_modulus
        } else {
            p.grain_young_modulus
        };
    }
    super::scene::set_tire_damping(&mut data, p.tire_damping)?;
    if p.diff_lock_torque > 0.0 {
        lock_differentials(&mut data, p.diff_lock_torque)?;
    }
    let radius = data.wheel.tire.radius();
    let lanes = if p.lane_width > 0.0 {
        // The tire and two grains either side of it must fit in a lane.
        let needed = data.wheel.tire.section_width() + 4.0 * p.grain_diameter;
        anyhow::ensure!(
            p.lane_width >= needed,
            "parameter `lane_width` = {} m: a lane must hold the tire ({} m wide) and two grains either side ({needed} m)",
            p.lane_width,
            data.wheel.tire.section_width()
        );
        let y = wheel_track_half_width(&data);
        vec![-y, y]
    } else {
        anyhow::ensure!(
            p.lane_width == 0.0,
            "parameter `lane_width` must be 0 (one bed) or > 0, got {}",
            p.lane_width
        );
        Vec::new()
    };
    let patch_params = GranularPatchParams {
        length: p.patch_length,
        width: if lanes.is_empty() {
            p.patch_width
        } else {
            p.lane_width
        },
        depth: p.depth,
        grain_radius: 0.5 * p.grain_diameter,
        density: p.grain_density,
        friction: p.mu,
        young_modulus: p.grain_young_modulus,
        restitution: 0.3,
        rolling_friction: p.rolling_friction,
        compliance: p.compliance,
        slab: (0.1 * p.patch_length).max(2.0 * p.grain_diameter),
        seed: 7,
        lanes,
    };
    let mut patch = GranularPatch::build(&mut sys, &patch_params, -0.5 * p.patch_length)?;
    let n_settle = n_steps(p.h, p.settle)?;
    for i in 1..=n_settle {
        sys.step(p.h)?;
        ctx.progress(0.2 * i as f64 / n_settle as f64);
    }
    patch.capture_settled(&sys)?;
    let surface = patch.surface();
    let z0 = start_height(&data, surface, p.drop_height);
    // The handling-tire terrain is not used by rigid tires; a flat one stands in.
    let flat = std::sync::Arc::new(FlatTerrain::new(surface, p.mu)?);
    let mut v =
        WheeledVehicle::build(&mut sys, &data, &Isometry3::translation(0.0, 0.0, z0), flat)?;
    // The front tires must stay clear of the front wall until the first relocation (at
    // `x = slab`, the vehicle reference in the middle of the patch).
    patch_params
        .check_room_for(front_reach(&data, p.grain_diameter))
        .map_err(|e| anyhow::anyhow!("parameter `patch_length`: {e}"))?;
    // Set down on the bed with the brakes on, then start rolling at `initial_speed`: the
    // landing is not part of the test.
    let n_land = if p.vehicle_settle > 0.0 {
        n_steps(p.h, p.vehicle_settle)?
    } else {
        0
    };
    let brakes = DriverInputs {
        throttle: 0.0,
        brake: 1.0,
        steering: 0.0,
    };
    for _ in 0..n_land {
        v.synchronize(&mut sys, brakes)?;
        sys.step(p.h)?;
    }
    v.set_forward_speed(&mut sys, p.initial_speed)?;
    // A PI controller: on loose ground the resistance needs a steady throttle that a
    // proportional controller only gives with a steady speed error.
    let gains = PidGains {
        kp: p.speed_kp,
        ki: p.speed_ki,
        kd: 0.0,
    };
    let mut speed = SpeedController::new(gains, p.speed)?;
    let traction = TractionControl::new(p.max_slip)?;
    let t_max = 3.0 * p.distance / p.speed + 5.0;
    let n_max = n_steps(p.h, t_max)?;
    let mut series = Series::new([
        "t",
        "x",
        "speed",
        "sinkage",
        "throttle",
        "brake",
        "wheel_speed",
        "residual",
        "iterations",
        "joint_violation",
    ]);
    let mut vtk = VtkFrames::new(ctx, (0.05 / p.h).round() as u64);
    let (mut sum_v, mut n_v, mut sum_sink, mut n_sink) = (0.0, 0usize, 0.0, 0usize);
    let t0 = sys.time();
    let x0 = v.state(&sys)?.position.x;
    let wall0 = Instant::now();
    let mut steps = 0;
    let mut distance = 0.0;
    // ANCF tires: grains whose centre got inside a carcass, counted every 50 steps.
    let mut inside_max = 0usize;
    for i in 1..=n_max {
        let st = v.state(&sys)?;
        patch.advance(&mut sys, st.position.x)?;
        let u = speed.advance(st.time, st.forward_speed());
        let (mut throttle, brake) = SpeedController::pedals(u);
        if p.max_slip > 0.0 {
            let wr = mean_wheel_surface_speed(&sys, &v, radius)?;
            throttle = traction.limit(throttle, wr, st.forward_speed());
        }
        let inputs = DriverInputs {
            throttle,
            brake,
            steering: 0.0,
        };
        v.synchronize(&mut sys, inputs)?;
        let report = sys.step(p.h)?;
        steps = i;
        vtk.record(i, &sys)?;
        let st = v.state(&sys)?;
        let t = sys.time() - t0;
        distance = st.position.x - x0;
        let sink = mean_sinkage(&sys, &v, surface, radius)?;
        let wheel_speed = mean_wheel_surface_speed(&sys, &v, radius)?;
        if t > 1.0 {
            sum_v += st.forward_speed();
            n_v += 1;
        }
        if distance > 0.5 * p.distance {
            sum_sink += sink;
            n_sink += 1;
        }
        if p.tire == TireKind::Ancf && i % 50 == 0 {
            inside_max = inside_max.max(grains_inside_tires(&sys, &v, &patch)?);
        }
        if i % 10 == 0 {
            series.push(&[
                t,
                distance,
                st.forward_speed(),
                sink,
                throttle,
                brake,
                wheel_speed,
                report.solve.residual,
                report.solve.iterations as f64,
                sys.max_joint_violation(),
            ]);
        }
        ctx.progress(0.2 + 0.8 * (distance / p.distance).clamp(0.0, 1.0));
        if distance >= p.distance {
            break;
        }
    }
    let wall = wall0.elapsed().as_secs_f64();
    vtk.finish()?;
    let mut out = CaseOutput::new();
    let mean_speed = if n_v > 0 { sum_v / n_v as f64 } else { 0.0 };
    out.check(Check::relative("mean_speed", mean_speed, p.speed, 0.1));
    out.check(Check::absolute(
        "distance",
        distance.min(p.distance),
        p.distance,
        1e-9,
    ));
    out.metric(
        "sinkage",
        if n_sink > 0 {
            sum_sink / n_sink as f64
        } else {
            f64::NAN
        },
    );
    if p.tire == TireKind::Ancf {
        out.check(Check::below("grains_inside_tires", inside_max as f64, 0.5));
    }
    out.metric("grains", patch.grains().len() as f64);
    out.metric("relocations", patch.relocations() as f64);
    out.metric("wall_s", wall);
    out.metric("real_time_factor", steps as f64 * p.h / wall);
    out.series = series;
    out.plot = PlotSpec::new(
        "HMMWV on a granular patch",
        "t [s]",
        "speed [m/s]",
        &["speed"],
    );
    out.steps = steps + n_settle + n_land;
    Ok(out)
}

/// The case.
pub fn case() -> Box<dyn Case> {
    ParamCase::<GranularParams>::boxed(
        "hmmwv-granular",
        "vehicle",
        "HMMWV holding 2 m/s with a speed controller on a moving granular patch (SMC grains by default): mean speed within 10 %, grains bounded over the distance.",
        run,
    )
}

/// Half the wheel track, m: the largest `|y|` of the axles' spindle points.
fn wheel_track_half_width(data: &chrono_vehicle::VehicleData) -> f64 {
    (data.axles.iter())
        .map(|a| a.suspension.points.spindle[1].abs())
        .fold(0.0, f64::max)
}

/// Grains whose centre lies inside an ANCF carcass
/// ([`WheeledVehicle::inside_ancf_tire`]), counted over the grains near each spindle.
fn grains_inside_tires(
    sys: &System,
    v: &WheeledVehicle,
    patch: &GranularPatch,
) -> anyhow::Result<usize> {
    let near = 1.1 * v.data().wheel.tire.radius();
    let mut count = 0;
    for &g in patch.grains() {
        let c = sys.body(g)?.position();
        for (i, w) in v.wheels().iter().enumerate() {
            if (sys.body(w.spindle)?.position() - c).norm() < near
                && v.inside_ancf_tire(sys, i, &c)?
            {
                count += 1;
                break;
            }
        }
    }
    Ok(count)
}
