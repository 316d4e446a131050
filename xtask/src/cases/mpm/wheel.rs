//! `mpm-wheel`: a rigid wheel driven at fixed slip under a vertical load on MPM sand
//! (plane strain, plain explicit MPM, two-way frictional contact; `chrono_mpm::wheel`),
//! beside Bekker's rigid-wheel sinkage from plate-sinkage runs on the same MPM sand.
//!
//! The wheel (radius `R`, width `b`, load `W`) rests on the soil bin's sand (Drucker–Prager
//! matched to Mohr–Coulomb in plane strain, geostatic start; `chrono_mpm::soil_bin`), the
//! load ramps up (static sinkage), then it drives at slip `s = 1 - v/(omega R)` for
//! `rim_travel` radii of rim travel; reported: the steady sinkage, drawbar pull, driving
//! torque and their ratios to the load (`DP/W`, `T/(W R)`).
//!
//! Bekker: two strip plates (`plate_width_small`, `plate_width_large`) pushed into the
//! same sand give `p(z)`; `p = (k_c/b + k_phi) z^n` is fitted over
//! `[fit_from, 1] plate_final_sinkage` (`chrono_mpm::plate::Bekker::fit`) and Wong's
//! rigid-wheel sinkage `z0 = [3W / ((3-n)(k_c + b k_phi) sqrt(D))]^(2/(2n+1))` (Wong,
//! Theory of Ground Vehicles, 4th ed., 2008, eq. 2.64) reported beside the wheel's own.
//! Bekker's law is a model, not a measurement: reported, not checked.
//!
//! Checked: the wheel's vertical equilibrium at steady state (the soil's mean vertical
//! force over the window equals the load within `equilibrium_tolerance`: Newton's second
//! law for a wheel whose height has stopped changing; it fails when the window is not
//! steady). `slip_sweep` (`--full`: 0, 0.1, 0.4) adds wheel runs at those slips,
//! reported.
//!
//! DEM side (`dem`, on by default, off in `--quick`): the same wheel (radius, width, load,
//! slip, rim speed, rim friction `tan(delta)`) on a granular slab by SMC
//! (`chrono_core::granular::wheel`): grains about the MPM cell in size, a slab `dem_slab`
//! grain diameters thick between frictionless walls (plane strain, as the MPM slab), the
//! bed's bulk density set to the sand's. The grains are those of `granular-shear` (glass
//! beads, `mu` 0.18), whose bulk friction its shear box measures (peak 27.6–29.0 degrees,
//! residual 23.3–23.8 degrees by SMC, `docs/validation-granular.md`) against the sand's
//! `friction_angle_deg`. Reported side by side (`dem_*`, their ratios to the MPM values,
//! `dem.csv`), not checked: no published result ties the two.

use chrono_core::granular::{PreparedBed, WheelBin, WheelRun};
use chrono_core::math::Vector3;
use chrono_core::{ContactMaterial, ContactMethod, SystemSettings};
use chrono_mpm::plate::{Bekker, Plate, PlateSample, PlateSpec};
use chrono_mpm::soil_bin::SoilSpec;
use chrono_mpm::wheel::{Wheel, WheelSpec};
use serde::{Deserialize, Serialize};

use crate::case::{Case, CaseOutput, Check, Mode, PlotSpec, RunContext, Series};
use crate::cases::granular::make_system;
use crate::params::{CaseParams, ParamCase, ParamInfo};

/// Parameters of `mpm-wheel`.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct WheelParams {
    /// Slip `s = 1 - v / (omega R)`.
    pub slip: f64,
    /// Vertical load, N.
    pub load: f64,
    /// Wheel radius, m.
    pub wheel_radius: f64,
    /// Wheel width, m.
    pub wheel_width: f64,
    /// Rim speed `omega R`, m/s.
    pub rim_speed: f64,
    /// Rim-soil friction angle, degrees (-1: the soil's).
    pub wheel_friction_angle_deg: f64,
    /// Friction angle of the sand, degrees.
    pub friction_angle_deg: f64,
    /// Cohesion of the sand, Pa.
    pub cohesion: f64,
    /// Young's modulus of the sand, Pa.
    pub young: f64,
    /// Poisson's ratio of the sand.
    pub poisson: f64,
    /// Bulk density of the sand, kg/m^3.
    pub density: f64,
    /// Gravity, m/s^2.
    pub gravity: f64,
    /// Grid cells across the wheel radius (the plates use the same spacing).
    pub cells: usize,
    /// Nodes lighter than this fraction of an interior node take no rim condition.
    pub contact_mass_fraction: f64,
    /// Markers per cell per axis.
    pub markers_per_cell: usize,
    /// Soil depth under the wheel, in radii.
    pub soil_depth: f64,
    /// Load ramp time, s.
    pub load_time: f64,
    /// Rim-speed ramp time, s.
    pub ramp_time: f64,
    /// Rim travel after the ramp, in radii.
    pub rim_travel: f64,
    /// Steady window: this last fraction of the drive.
    pub average_fraction: f64,
    /// CFL number.
    pub cfl: f64,
    /// FLIP fraction of the velocity update (0: APIC).
    pub flip: f64,
    /// The smaller plate's width, m.
    pub plate_width_small: f64,
    /// The larger plate's width, m.
    pub plate_width_large: f64,
    /// Final plate sinkage, m.
    pub plate_final_sinkage: f64,
    /// Plate speed, m/s.
    pub plate_speed: f64,
    /// Bekker's fit uses the samples from this fraction of the final plate sinkage on.
    pub fit_from: f64,
    /// Relative tolerance of the vertical equilibrium check.
    pub equilibrium_tolerance: f64,
    /// More wheel runs at these slips (reported: sinkage, DP/W, T/(W R) per slip).
    pub slip_sweep: Vec<f64>,
    /// Run the same wheel on a granular bed by DEM (SMC) beside the MPM one.
    pub dem: bool,
    /// DEM: largest grain diameter `d`, m.
    pub dem_grain_diameter: f64,
    /// DEM: smallest over largest grain diameter.
    pub dem_size_ratio: f64,
    /// DEM: slab thickness across the travel, in `d` (frictionless side walls).
    pub dem_slab: f64,
    /// DEM: grain Young's modulus (SMC Hertz), Pa.
    pub dem_young: f64,
    /// DEM: grain Poisson's ratio.
    pub dem_poisson: f64,
    /// DEM: restitution.
    pub dem_restitution: f64,
    /// DEM: grain–grain sliding friction.
    pub dem_mu: f64,
    /// DEM: rolling friction coefficient.
    pub dem_rolling_friction: f64,
    /// DEM: seed of the packing.
    pub dem_seed: u64,
}

impl Default for WheelParams {
    fn default() -> Self {
        let w = WheelSpec::default();
        let s = SoilSpec::default();
        Self {
            slip: w.slip,
            load: w.load,
            wheel_radius: w.wheel_radius,
            wheel_width: w.wheel_width,
            rim_speed: w.rim_speed,
            wheel_friction_angle_deg: -1.0,
            friction_angle_deg: s.friction_angle_deg,
            cohesion: s.cohesion,
            young: s.young,
            poisson: s.poisson,
            density: s.density,
            gravity: s.gravity,
            cells: w.cells_radius,
            contact_mass_fraction: w.contact_mass_fraction,
            markers_per_cell: s.markers_per_cell,
            soil_depth: w.soil_depth,
            load_time: w.load_time,
            ramp_time: w.ramp_time,
            rim_travel: w.rim_travel,
            average_fraction: w.average_fraction,
            cfl: s.cfl,
            flip: s.flip,
            plate_width_small: 0.125,
            plate_width_large: 0.25,
            plate_final_sinkage: 0.08,
            plate_speed: 0.2,
            fit_from: 0.25,
            equilibrium_tolerance: 0.05,
            slip_sweep: Vec::new(),
            dem: true,
            // R / d = 6.25, b / d = 3.75, about the MPM cell (R / 8 = 0.031 m): the budget's
            // size (0.035 and 0.03 m move the sinkage by < 5 %, docs/mpm.md).
            dem_grain_diameter: 0.04,
            dem_size_ratio: 0.8,
            dem_slab: 3.0,
            // The glass beads of `granular-shear` (Fleischmann's parameters after Härtl
            // and Ooi 2008), whose bulk friction that case measures.
            dem_young: 4e7,
            dem_poisson: 0.22,
            dem_restitution: 0.87,
            dem_mu: 0.18,
            dem_rolling_friction: 0.0,
            dem_seed: 1,
        }
    }
}

impl CaseParams for WheelParams {
    const INFO: &'static [ParamInfo] = &[
        ParamInfo::new("slip", "-", "slip s = 1 - v/(omega R), in [-1, 1]"),
        ParamInfo::new("load", "N", "vertical load on the wheel (its weight)"),
        ParamInfo::new("wheel_radius", "m", "wheel radius R"),
        ParamInfo::new(
            "wheel_width",
            "m",
            "wheel width b (the slab's forces are scaled to it)",
        ),
        ParamInfo::new("rim_speed", "m/s", "rim speed omega R"),
        ParamInfo::new(
            "wheel_friction_angle_deg",
            "deg",
            "rim-soil Coulomb friction angle (-1: the sand's)",
        ),
        ParamInfo::new("friction_angle_deg", "deg", "friction angle of the sand"),
        ParamInfo::new("cohesion", "Pa", "cohesion of the sand"),
        ParamInfo::new("young", "Pa", "Young's modulus of the sand"),
        ParamInfo::new("poisson", "-", "Poisson's ratio of the sand"),
        ParamInfo::new("density", "kg/m^3", "bulk density of the sand"),
        ParamInfo::new("gravity", "m/s^2", "gravity"),
        ParamInfo::new(
            "cells",
            "-",
            "grid cells across the wheel radius (plates: same dx)",
        ),
        ParamInfo::new(
            "contact_mass_fraction",
            "-",
            "nodes lighter than this fraction of an interior node's mass take no rim condition (0: all nodes with mass)",
        ),
        ParamInfo::new("markers_per_cell", "-", "markers per cell per axis"),
        ParamInfo::new("soil_depth", "R", "soil depth under the wheel, in radii"),
        ParamInfo::new("load_time", "s", "load ramp (wheel at rest)"),
        ParamInfo::new("ramp_time", "s", "rim-speed ramp"),
        ParamInfo::new("rim_travel", "R", "rim travel after the ramp, in radii"),
        ParamInfo::new(
            "average_fraction",
            "-",
            "the steady values are means over this last fraction of the drive",
        ),
        ParamInfo::new("cfl", "-", "CFL number"),
        ParamInfo::new(
            "flip",
            "-",
            "FLIP fraction of the velocity update (0: APIC)",
        ),
        ParamInfo::new("plate_width_small", "m", "the smaller Bekker plate's width"),
        ParamInfo::new("plate_width_large", "m", "the larger Bekker plate's width"),
        ParamInfo::new("plate_final_sinkage", "m", "final plate sinkage"),
        ParamInfo::new("plate_speed", "m/s", "plate speed"),
        ParamInfo::new(
            "fit_from",
            "-",
            "Bekker's fit uses the plate samples from this fraction of the final sinkage on",
        ),
        ParamInfo::new(
            "equilibrium_tolerance",
            "-",
            "relative tolerance of the steady vertical equilibrium (soil force = load)",
        ),
        ParamInfo::new(
            "slip_sweep",
            "-",
            "more wheel runs at these slips, reported (--full: 0, 0.1, 0.4)",
        ),
        ParamInfo::new(
            "dem",
            "-",
            "also the same wheel on a DEM (SMC) granular slab, reported side by side (--quick: off)",
        ),
        ParamInfo::new(
            "dem_grain_diameter",
            "m",
            "DEM largest grain diameter d (--full: 0.02)",
        ),
        ParamInfo::new(
            "dem_size_ratio",
            "-",
            "DEM smallest over largest grain diameter",
        ),
        ParamInfo::new(
            "dem_slab",
            "d",
            "DEM slab thickness across the travel (frictionless side walls)",
        ),
        ParamInfo::new("dem_young", "Pa", "DEM grain Young's modulus (SMC Hertz)"),
        ParamInfo::new("dem_poisson", "-", "DEM grain Poisson's ratio"),
        ParamInfo::new("dem_restitution", "-", "DEM restitution"),
        ParamInfo::new("dem_mu", "-", "DEM grain-grain sliding friction"),
        ParamInfo::new(
            "dem_rolling_friction",
            "-",
            "DEM rolling friction coefficient",
        ),
        ParamInfo::new("dem_seed", "-", "DEM seed of the packing"),
    ];

    fn apply_mode(&mut self, mode: Mode) {
        match mode {
            Mode::Quick => {
                self.rim_travel = 1.5;
                self.plate_final_sinkage = 0.06;
                // The DEM side alone takes longer than the quick budget.
                self.dem = false;
            }
            // The DEM side (~12 s idle) does not fit the main command's plan either: it
            // reports under `--full` or `--set dem=true`.
            Mode::Default => {
                self.dem = false;
            }
            Mode::Full => {
                self.cells = 16;
                self.slip_sweep = vec![0.0, 0.1, 0.4];
                self.dem_grain_diameter = 0.02;
            }
        }
    }
}

fn soil(p: &WheelParams) -> SoilSpec {
    SoilSpec {
        friction_angle_deg: p.friction_angle_deg,
        cohesion: p.cohesion,
        young: p.young,
        poisson: p.poisson,
        density: p.density,
        gravity: p.gravity,
        markers_per_cell: p.markers_per_cell,
        cfl: p.cfl,
        flip: p.flip,
    }
}

fn run(p: &WheelParams, ctx: &RunContext) -> anyhow::Result<CaseOutput> {
    anyhow::ensure!(
        p.fit_from > 0.0 && p.fit_from < 1.0,
        "fit_from must lie in (0, 1), got {}",
        p.fit_from
    );
    let delta = if p.wheel_friction_angle_deg < 0.0 {
        p.friction_angle_deg
    } else {
        p.wheel_friction_angle_deg
    };
    let spec = |slip: f64| WheelSpec {
        soil: soil(p),
        wheel_radius: p.wheel_radius,
        wheel_width: p.wheel_width,
        load: p.load,
        wheel_mass: None,
        slip,
        rim_speed: p.rim_speed,
        wheel_friction_angle_deg: delta,
        cells_radius: p.cells,
        contact_mass_fraction: p.contact_mass_fraction,
        soil_depth: p.soil_depth,
        load_time: p.load_time,
        ramp_time: p.ramp_time,
        rim_travel: p.rim_travel,
        average_fraction: p.average_fraction,
    };
    let runs = 1 + p.slip_sweep.len();
    // The MPM runs' share of the progress (the DEM side takes the rest).
    let part = if p.dem { 0.5 } else { 1.0 };
    let share = 0.6 / runs as f64;
    let mut wheel = Wheel::new(spec(p.slip))?;
    let dx = wheel.body.spec().dx;
    let markers = wheel.body.markers.len();
    let r = wheel.run(|x| ctx.progress(part * share * x))?;
    let mut steps = r.steps;
    let mut sweep = Vec::with_capacity(p.slip_sweep.len());
    for (k, &slip) in p.slip_sweep.iter().enumerate() {
        let mut w = Wheel::new(spec(slip))?;
        let q = w.run(|x| ctx.progress(part * share * (k as f64 + 1.0 + x)))?;
        steps += q.steps;
        sweep.push((slip, q));
    }
    // The plates on the same sand and grid spacing.
    let mut curves: Vec<(f64, Vec<PlateSample>)> = Vec::new();
    for (k, b) in [p.plate_width_small, p.plate_width_large]
        .into_iter()
        .enumerate()
    {
        let mut plate = Plate::new(PlateSpec {
            soil: soil(p),
            plate_width: b,
            dx,
            domain_width: 3.0,
            domain_depth: 2.0,
            final_sinkage: p.plate_final_sinkage,
            speed: p.plate_speed,
            ramp_time: 0.05,
        })?;
        let s = plate.run(40, |x| ctx.progress(part * (0.6 + 0.2 * (k as f64 + x))))?;
        steps += plate.body.steps();
        curves.push((b, s));
    }
    let zf = p.plate_final_sinkage;
    let fit = Bekker::fit(
        [(curves[0].0, &curves[0].1), (curves[1].0, &curves[1].1)],
        p.fit_from * zf,
        zf,
    )?;
    let z_bekker = fit.wheel_sinkage(p.load, 2.0 * p.wheel_radius, p.wheel_width);

    let wr = p.load * p.wheel_radius;
    let mut out = CaseOutput::new();
    out.check(Check::relative(
        "vertical_force",
        r.vertical_force,
        p.load,
        p.equilibrium_tolerance,
    ));
    out.metric("sinkage", r.sinkage);
    out.metric("static_sinkage", r.static_sinkage);
    out.metric("sinkage_cells", r.sinkage / dx);
    out.metric("drawbar_pull", r.drawbar_pull);
    out.metric("torque", r.torque);
    out.metric("drawbar_pull_ratio", r.drawbar_pull / p.load);
    out.metric("torque_ratio", r.torque / wr);
    out.metric("bekker_k_c", fit.k_c);
    out.metric("bekker_k_phi", fit.k_phi);
    out.metric("bekker_n", fit.n);
    out.metric("bekker_fit_rms_log", fit.rms_log);
    out.metric("bekker_sinkage", z_bekker);
    out.metric("sinkage_over_bekker", r.sinkage / z_bekker);
    out.metric("markers", markers as f64);
    for (slip, q) in &sweep {
        out.metric(format!("sinkage_s{slip}"), q.sinkage);
        out.metric(
            format!("drawbar_pull_ratio_s{slip}"),
            q.drawbar_pull / p.load,
        );
        out.metric(format!("torque_ratio_s{slip}"), q.torque / wr);
        ctx.note(format!(
            "slip {slip}: sinkage {:.4} m, DP/W {:.3}, T/(W R) {:.3}, F_z/W {:.3}",
            q.sinkage,
            q.drawbar_pull / p.load,
            q.torque / wr,
            q.vertical_force / p.load
        ));
    }
    ctx.note(format!(
        "wheel: {markers} markers, dx {dx:.4} m, {} steps; slip {}: sinkage {:.4} m ({:.2} cells; static {:.4} m), DP {:.1} N (DP/W {:.3}), T {:.2} N m (T/(W R) {:.3}), F_z/W {:.3}",
        r.steps,
        p.slip,
        r.sinkage,
        r.sinkage / dx,
        r.static_sinkage,
        r.drawbar_pull,
        r.drawbar_pull / p.load,
        r.torque,
        r.torque / wr,
        r.vertical_force / p.load
    ));
    ctx.note(format!(
        "Bekker fit (plates {} and {} m, z in [{:.3}, {:.3}] m): k_c {:.4e} N/m^(n+1), k_phi {:.4e} N/m^(n+2), n {:.3} (rms ln p {:.3}); Wong's z0 {:.4} m against the wheel's {:.4} m.",
        p.plate_width_small,
        p.plate_width_large,
        p.fit_from * zf,
        zf,
        fit.k_c,
        fit.k_phi,
        fit.n,
        fit.rms_log,
        z_bekker,
        r.sinkage
    ));
    if p.dem {
        let dem = run_dem(p, delta, |x| ctx.progress(part + (1.0 - part) * x))?;
        steps += dem.run.steps + dem.settle_steps;
        report_dem(p, &dem, &r, &mut out, ctx)?;
    }
    let mut series = Series::new([
        "travel_over_r",
        "sinkage_over_r",
        "drawbar_pull_over_w",
        "torque_over_wr",
        "vertical_force_over_w",
    ]);
    for s in &r.samples {
        series.push(&[
            s.travel / p.wheel_radius,
            s.sinkage / p.wheel_radius,
            s.drawbar_pull / p.load,
            s.torque / wr,
            s.vertical_force / p.load,
        ]);
    }
    out.series = series;
    out.plot = PlotSpec::new(
        "MPM rigid wheel at fixed slip: sinkage, drawbar pull, torque",
        "travel / R",
        "ratio",
        &[
            "sinkage_over_r",
            "drawbar_pull_over_w",
            "torque_over_wr",
            "vertical_force_over_w",
        ],
    );
    // The plate curves beside it.
    let mut plates = String::from("plate_width,sinkage,pressure,bekker_pressure\n");
    for (b, s) in &curves {
        for q in s {
            plates.push_str(&format!(
                "{b},{},{},{}\n",
                q.sinkage,
                q.pressure,
                fit.pressure(*b, q.sinkage)
            ));
        }
    }
    std::fs::write(ctx.out_file("plates.csv"), plates)?;
    out.steps = steps;
    Ok(out)
}

/// The DEM side's results.
struct DemSide {
    spec: WheelBin,
    bed: PreparedBed,
    run: WheelRun,
    settle_steps: u64,
    wall: f64,
}

/// The same wheel (radius, width, load, slip, rim speed, rim friction `tan(delta)`) on a
/// DEM slab of the bulk density of the MPM sand (`chrono_core::granular::wheel`), SMC.
fn run_dem(
    p: &WheelParams,
    delta_deg: f64,
    mut progress: impl FnMut(f64),
) -> anyhow::Result<DemSide> {
    let start = std::time::Instant::now();
    let d = p.dem_grain_diameter;
    let material = ContactMaterial::smc(p.dem_young, p.dem_poisson, p.dem_restitution, p.dem_mu)
        .with_rolling_friction(p.dem_rolling_friction);
    let spec = WheelBin {
        rim_speed: p.rim_speed,
        rim_friction: delta_deg.to_radians().tan(),
        size_ratio: p.dem_size_ratio,
        slab_thickness: p.dem_slab * d,
        soil_depth: p.soil_depth * p.wheel_radius,
        load_time: p.load_time,
        ramp_time: p.ramp_time,
        rim_travel: p.rim_travel,
        average_fraction: p.average_fraction,
        seed: p.dem_seed,
        ..WheelBin::new(
            p.wheel_radius,
            p.wheel_width,
            p.load,
            p.slip,
            d,
            p.density,
            material,
        )
    };
    let gravity = Vector3::new(0.0, 0.0, -p.gravity);
    let system = |v: f64| {
        let mut settings = SystemSettings {
            gravity,
            envelope: 0.05 * d,
            ..SystemSettings::default()
        };
        // The fastest contact of the run is a grain struck by the rim at its speed; the
        // pour's grains land at about 1 m/s.
        settings.smc.characteristic_velocity = v;
        make_system(ContactMethod::Smc, settings, 1e-6, 50)
    };
    let bed = spec.prepare(&mut system(1.0)?)?;
    progress(0.25);
    let run = spec.run(&mut system(p.rim_speed)?, &bed, |x| {
        progress(0.25 + 0.75 * x)
    })?;
    Ok(DemSide {
        spec,
        settle_steps: bed.steps,
        bed,
        run,
        wall: start.elapsed().as_secs_f64(),
    })
}

/// The DEM side's metrics and notes, and `dem.csv` (its samples).
fn report_dem(
    p: &WheelParams,
    dem: &DemSide,
    mpm: &chrono_mpm::wheel::WheelResult,
    out: &mut CaseOutput,
    ctx: &RunContext,
) -> anyhow::Result<()> {
    let q = &dem.run;
    let wr = p.load * p.wheel_radius;
    out.metric("dem_sinkage", q.sinkage);
    out.metric("dem_static_sinkage", q.static_sinkage);
    out.metric("dem_drawbar_pull", q.drawbar_pull);
    out.metric("dem_torque", q.torque);
    out.metric("dem_drawbar_pull_ratio", q.drawbar_pull / p.load);
    out.metric("dem_torque_ratio", q.torque / wr);
    out.metric("dem_vertical_force_ratio", q.vertical_force / p.load);
    out.metric("dem_over_mpm_sinkage", q.sinkage / mpm.sinkage);
    out.metric(
        "dem_over_mpm_static_sinkage",
        q.static_sinkage / mpm.static_sinkage,
    );
    out.metric(
        "dem_over_mpm_drawbar_pull",
        q.drawbar_pull / mpm.drawbar_pull,
    );
    out.metric("dem_over_mpm_torque", q.torque / mpm.torque);
    out.metric("dem_bulk_density", q.bulk_density);
    out.metric("dem_solid_fraction", dem.bed.solid_fraction);
    out.metric("dem_grains", q.grains as f64);
    out.metric("dem_grain_over_width", p.dem_grain_diameter / p.wheel_width);
    out.metric("dem_wall_s", dem.wall);
    ctx.note(format!(
        "DEM (SMC): {} grains of {:.3} m (d/b {:.2}, R/d {:.1}; slab {:.3} m), grain density {:.0} kg/m^3 for a bulk density of {:.0} (solid fraction {:.3}), bed {:.3} m deep (roughness {:.4} m); h {:.2e} s, {} + {} steps, {:.1} s wall. Slip {}: sinkage {:.4} m (static {:.4}), DP {:.1} N (DP/W {:.3}), T {:.2} N m (T/(W R) {:.3}), F_z/W {:.3}; DEM/MPM: sinkage {:.2}, DP {:.2}, T {:.2}. Grains of granular-shear (mu {}, rolling {}): its SMC shear box measured 27.6-29.0 deg peak, 23.3-23.8 deg residual at mu 0.18 without rolling friction (docs/validation-granular.md), against the sand's {} deg.",
        q.grains,
        p.dem_grain_diameter,
        p.dem_grain_diameter / p.wheel_width,
        p.wheel_radius / p.dem_grain_diameter,
        dem.spec.slab_thickness,
        dem.bed.grain_density,
        q.bulk_density,
        dem.bed.solid_fraction,
        q.surface,
        q.roughness,
        q.h,
        dem.settle_steps,
        q.steps,
        dem.wall,
        p.slip,
        q.sinkage,
        q.static_sinkage,
        q.drawbar_pull,
        q.drawbar_pull / p.load,
        q.torque,
        q.torque / wr,
        q.vertical_force / p.load,
        q.sinkage / mpm.sinkage,
        q.drawbar_pull / mpm.drawbar_pull,
        q.torque / mpm.torque,
        p.dem_mu,
        p.dem_rolling_friction,
        p.friction_angle_deg,
    ));
    let mut csv = String::from(
        "t,travel_over_r,sinkage_over_r,drawbar_pull_over_w,torque_over_wr,vertical_force_over_w\n",
    );
    for s in &q.samples {
        csv.push_str(&format!(
            "{},{},{},{},{},{}\n",
            s.t,
            s.travel / p.wheel_radius,
            s.sinkage / p.wheel_radius,
            s.drawbar_pull / p.load,
            s.torque / wr,
            s.vertical_force / p.load
        ));
    }
    std::fs::write(ctx.out_file("dem.csv"), csv)?;
    Ok(())
}

/// The case.
pub fn case() -> Box<dyn Case> {
    ParamCase::<WheelParams>::boxed(
        "mpm-wheel",
        "mpm",
        "Rigid wheel at fixed slip under a vertical load on Drucker-Prager sand (plane strain, two-way frictional contact): steady sinkage, drawbar pull and torque reported beside Bekker's rigid-wheel sinkage from plate tests on the same sand (Wong eq. 2.64) and the same wheel on a DEM (SMC) granular slab of the same bulk density (reported side by side); checked: the steady vertical equilibrium.",
        run,
    )
}
