//! `mpm-column-collapse --set method=nsc`: the same column by granular DEM (NSC) of
//! chrono-core (`chrono_core::granular::column`), the MPM column beside it at the angle
//! of the DEM material's shear-box measurement (the parent module's docs and
//! `docs/mpm.md`, "The DEM side").

use chrono_core::granular::GranularColumn;
use chrono_core::{ContactMaterial, ContactMethod, System, SystemSettings};
use chrono_mpm::column::Column;
use nalgebra::Vector3;

use super::*;
use crate::cases::granular::make_system;

/// The DEM column of the case's parameters at `a`.
fn dem_spec(p: &ColumnParams, a: f64) -> GranularColumn {
    GranularColumn {
        size_ratio: p.size_ratio,
        slab_width: p.slab_width,
        density: p.grain_density,
        rough_floor: p.rough_floor,
        seed: p.dem_seed,
        h: p.dem_step,
        settle_iterations: (p.dem_settle_iterations > 0).then_some(p.dem_settle_iterations),
        rest_kinetic: p.rest_kinetic,
        rest_window: p.rest_window,
        max_time: p.max_time,
        ..GranularColumn::new(
            a,
            p.column_length,
            p.grains_across,
            ContactMaterial::with_friction(p.contact_friction)
                .with_rolling_friction(p.rolling_friction),
        )
    }
}

/// The NSC system of the DEM column: gravity `-g z`, envelope `0.1 d`, APGD.
fn dem_system(p: &ColumnParams) -> anyhow::Result<System> {
    let d = p.column_length / p.grains_across;
    let settings = SystemSettings {
        gravity: Vector3::new(0.0, 0.0, -p.gravity),
        envelope: 0.1 * d,
        max_recovery_speed: p.dem_recovery_speed,
        ..SystemSettings::default()
    };
    make_system(
        ContactMethod::Nsc,
        settings,
        p.dem_tolerance,
        p.dem_max_iterations,
    )
}

/// The MPM sand's friction angle beside the DEM column (`matched_friction_angle_deg`).
fn matched_angle(p: &ColumnParams) -> anyhow::Result<f64> {
    if p.matched_friction_angle_deg >= 0.0 {
        anyhow::ensure!(
            p.matched_friction_angle_deg > 0.0 && p.matched_friction_angle_deg < 90.0,
            "parameter `matched_friction_angle_deg` must lie in (0, 90) degrees, got {}",
            p.matched_friction_angle_deg
        );
        return Ok(p.matched_friction_angle_deg);
    }
    anyhow::ensure!(
        p.contact_friction == RECORDED_CONTACT_FRICTION && p.rolling_friction == 0.0,
        "parameter `matched_friction_angle_deg` < 0 takes the recorded shear-box angle of contact_friction {RECORDED_CONTACT_FRICTION}, rolling_friction 0; this material (contact_friction {}, rolling_friction {}) has none: measure it (`xtask validate granular-shear --set 'method=[\"nsc\"]' --set mu={} --set rolling_friction={} ...`, docs/mpm.md) and give it",
        p.contact_friction,
        p.rolling_friction,
        p.contact_friction,
        p.rolling_friction
    );
    Ok(SHEAR_BOX_RESIDUAL_DEG)
}

/// `method = nsc`: the DEM column at each ratio, the MPM column at the matched angle beside.
pub(super) fn run_nsc(
    p: &ColumnParams,
    ctx: &RunContext,
    f_bar: FBar,
    critical_state: Option<CriticalStateSand>,
    split: bool,
) -> anyhow::Result<CaseOutput> {
    let angle = matched_angle(p)?;
    let mut ratios: Vec<f64> = p.dem_sweep.clone().unwrap_or_else(|| p.sweep.clone());
    ratios.push(p.aspect_ratio);
    for &a in &ratios {
        anyhow::ensure!(
            a.is_finite() && a > 0.0,
            "parameter `dem_sweep`/`sweep`/`aspect_ratio`: aspect ratios must be finite and > 0, got {a}"
        );
    }
    ratios.sort_by(f64::total_cmp);
    ratios.dedup();
    anyhow::ensure!(
        p.dem_step.is_finite() && p.dem_step >= 0.0,
        "parameter `dem_step` must be finite and >= 0 s (0: 1 ms), got {}",
        p.dem_step
    );
    for &a in &ratios {
        dem_spec(p, a)
            .validate()
            .map_err(|e| anyhow::anyhow!("mpm-column-collapse (nsc): {e}"))?;
    }
    dem_system(p)?;
    let mpm_p = ColumnParams {
        friction_angle_deg: angle,
        floor_friction_angle_deg: -1.0,
        ..p.clone()
    };
    if p.mpm_beside {
        for &a in &ratios {
            Column::new(spec(&mpm_p, a, f_bar, critical_state))?;
        }
    }
    let mut out = CaseOutput::new();
    let weight = |a: f64| a.max(1.0).powf(2.0);
    let total: f64 = ratios.iter().map(|&a| weight(a)).sum();
    let dem_share = if p.mpm_beside { 0.9 } else { 1.0 };
    let mut done = 0.0;
    let mut dem_pts = Vec::new();
    let (mut dem_wall, mut dem_grain_steps, mut steps) = (0.0, 0.0, 0u64);
    for &a in &ratios {
        let spec = dem_spec(p, a);
        let mut sys = dem_system(p)?;
        let w = weight(a) / total;
        let wall = std::time::Instant::now();
        let mut scene = spec
            .build(&mut sys, |_, _| Ok::<(), anyhow::Error>(()))
            .map_err(|e| anyhow::anyhow!("mpm-column-collapse (nsc), a = {a}: {e}"))?;
        let settle_s = wall.elapsed().as_secs_f64();
        let tau = (scene.initial_height() / p.gravity).sqrt();
        let n_max = (p.max_time * tau / scene.h()).ceil();
        let r = scene
            .run(&mut sys, |_, k| {
                if k.is_multiple_of(32) {
                    ctx.progress(dem_share * (done + w * (k as f64 / n_max).min(1.0)));
                }
                Ok::<(), anyhow::Error>(())
            })
            .map_err(|e| anyhow::anyhow!("mpm-column-collapse (nsc), a = {a}: {e}"))?;
        done += w;
        let wall_s = wall.elapsed().as_secs_f64();
        let grain_steps = (r.grains as u64 * (r.steps + r.settle_steps)) as f64;
        let (lo, hi) = envelope(a);
        ctx.note(format!(
            "DEM a = {a} (built {:.3}{}): runout ratio {:.3} (farthest grain {:.3}, 99 % mass {:.3}; envelope [{lo:.3}, {hi:.3}]), final height ratio {:.3} (Lube {:.3}), {} at t = {:.2} sqrt(H0/g); {} grains (solid fraction {:.3}), {} + {} steps, {:.1} iterations per step, {wall_s:.1} s wall ({settle_s:.1} s settling), {:.3e} grain-steps/s",
            r.aspect_ratio,
            if r.settled {
                String::new()
            } else {
                format!(
                    ", gate opened at t_settle with {:.1e} m g d per grain",
                    r.settled_ke
                )
            },
            r.runout_ratio,
            r.runout_ratio_farthest,
            r.runout_ratio_99,
            r.final_height_ratio,
            lube_height_ratio(a),
            if r.at_rest { "at rest" } else { "NOT at rest" },
            r.time / r.time_scale,
            r.grains,
            r.solid_fraction,
            r.settle_steps,
            r.steps,
            r.iterations,
            grain_steps / wall_s,
        ));
        if !r.at_rest {
            // A grain rocking on the deposit keeps a small column above the criterion
            // (1e-4 M g H0 is a few grains' energy at a = 0.5): reported, not an error.
            ctx.note(format!(
                "the DEM column at a = {a} did not meet the rest criterion within max_time = {} sqrt(H0/g): its deposit is measured at the end",
                p.max_time
            ));
        }
        anyhow::ensure!(
            (r.mass_ratio - 1.0).abs() < 1e-12 && r.escaped == 0,
            "the DEM column at a = {a} lost grains: mass ratio {}, {} outside the slab",
            r.mass_ratio,
            r.escaped
        );
        let tag = format!("a{a}_dem");
        out.metric(format!("runout_ratio_{tag}"), r.runout_ratio)
            .metric(
                format!("runout_ratio_farthest_{tag}"),
                r.runout_ratio_farthest,
            )
            .metric(format!("runout_ratio_99_{tag}"), r.runout_ratio_99)
            .metric(format!("final_height_ratio_{tag}"), r.final_height_ratio)
            .metric(format!("aspect_ratio_built_{tag}"), r.aspect_ratio)
            .metric(format!("solid_fraction_{tag}"), r.solid_fraction)
            .metric(format!("grains_{tag}"), r.grains as f64)
            .metric(format!("detached_grains_{tag}"), r.deposit.detached as f64)
            .metric(format!("steps_{tag}"), r.steps as f64)
            .metric(format!("settle_steps_{tag}"), r.settle_steps as f64)
            .metric(format!("settled_ke_over_mgd_{tag}"), r.settled_ke)
            .metric(format!("rest_time_over_tau_{tag}"), r.time / r.time_scale)
            .metric(format!("at_rest_{tag}"), if r.at_rest { 1.0 } else { 0.0 })
            .metric(format!("iterations_per_step_{tag}"), r.iterations)
            .metric(format!("wall_s_{tag}"), wall_s)
            .metric(format!("grain_steps_per_s_{tag}"), grain_steps / wall_s);
        dem_wall += wall_s;
        dem_grain_steps += grain_steps;
        steps += r.steps + r.settle_steps;
        dem_pts.push(Point {
            a,
            runout: r.runout_ratio,
            height: r.final_height_ratio,
        });
    }
    report(
        p,
        ctx,
        &mut out,
        &dem_pts,
        "Granular column collapse by DEM (NSC): runout against aspect ratio",
    );
    slope_metrics(&mut out, &dem_pts, "dem");
    out.metric("matched_friction_angle_deg", angle)
        .metric("shear_box_peak_deg", SHEAR_BOX_PEAK_DEG)
        .metric("envelope_excess_dem", envelope_excess(&dem_pts))
        .metric("wall_s_dem", dem_wall)
        .metric("grain_steps_per_s_dem", dem_grain_steps / dem_wall);
    if p.mpm_beside {
        let mpm = run_mpm(
            &mpm_p,
            ctx,
            &ratios,
            f_bar,
            critical_state,
            split,
            (dem_share, 1.0 - dem_share),
            "MPM (matched angle) ",
        )?;
        let mut mpm_pts = Vec::new();
        let (mut wall, mut marker_steps) = (0.0, 0.0);
        for (a, r, wall_s, markers) in &mpm {
            let tag = format!("a{a}_mpm");
            out.metric(format!("runout_ratio_{tag}"), r.runout_ratio)
                .metric(format!("final_height_ratio_{tag}"), r.final_height_ratio)
                .metric(format!("steps_{tag}"), r.steps as f64)
                .metric(format!("wall_s_{tag}"), *wall_s);
            wall += wall_s;
            marker_steps += (*markers as u64 * r.steps) as f64;
            steps += r.steps;
            mpm_pts.push(Point {
                a: *a,
                runout: r.runout_ratio,
                height: r.final_height_ratio,
            });
        }
        slope_metrics(&mut out, &mpm_pts, "mpm");
        out.metric("envelope_excess_mpm", envelope_excess(&mpm_pts))
            .metric("wall_s_mpm", wall)
            .metric("marker_steps_per_s_mpm", marker_steps / wall);
        for (d, m) in dem_pts.iter().zip(&mpm_pts) {
            ctx.note(format!(
                "a = {}: runout ratio DEM {:.3}, MPM {:.3} (phi {angle:.2}); final height ratio DEM {:.3}, MPM {:.3}",
                d.a, d.runout, m.runout, d.height, m.height
            ));
        }
        let mut series = Series::new([
            "aspect_ratio",
            "runout_ratio_dem",
            "runout_ratio_mpm",
            "lube_2005",
            "lajeunesse_2005",
            "final_height_ratio_dem",
            "final_height_ratio_mpm",
            "final_height_ratio_lube",
        ]);
        for (d, m) in dem_pts.iter().zip(&mpm_pts) {
            let fit = |f: &Fit| {
                let v = f.values(d.a);
                v.iter().sum::<f64>() / v.len() as f64
            };
            series.push(&[
                d.a,
                d.runout,
                m.runout,
                fit(&LUBE),
                fit(&LAJEUNESSE),
                d.height,
                m.height,
                lube_height_ratio(d.a),
            ]);
        }
        out.series = series;
        out.plot = PlotSpec::new(
            "Granular column collapse, DEM (NSC) and MPM at the shear-box angle",
            "a = H0 / L0",
            "(L_inf - L0) / L0",
            &[
                "runout_ratio_dem",
                "runout_ratio_mpm",
                "lube_2005",
                "lajeunesse_2005",
            ],
        );
    }
    out.steps = steps;
    Ok(out)
}
