//! The scene of `granular-repose` (see `repose.rs` for the reference and the checks): a
//! bed settled between two gates on a plate in a slot, discharged over both edges, and the
//! angle of the heap that stays, fitted to the highest grain centre of each column.

use chrono_core::granular::probe::{flank_angles, heap_profile};
use chrono_core::granular::{GrainBed, Kick, Region, Settle};
use chrono_core::math::{Isometry3, UnitQuaternion, Vector3};
use chrono_core::system::ContactMethod;
use chrono_core::{
    BodyHandle, ContactFriction, ContactMaterial, RigidBodyBuilder, Shape, System, SystemSettings,
};

use super::repose::ReposeParams;
use super::{grain_frames, make_system, record_grains};
use crate::case::RunContext;

/// The heap left on the plate by one run.
pub(super) struct Heap {
    /// Angle of both flanks fitted together, degrees.
    pub angle: f64,
    /// Angles of the left (x < 0) and right flanks, degrees.
    pub flanks: [f64; 2],
    /// Highest grain centre above the plate, m.
    pub crest: f64,
    pub grains: usize,
    pub on_plate: usize,
    /// Kinetic energy per grain on the plate at the end, in `m g d`.
    pub ke: f64,
    pub steps: u64,
    pub wall_s: f64,
    /// Surface: column centre x (m) and its highest grain centre z (m), NaN if empty.
    pub profile: Vec<(f64, f64)>,
}

/// A fixed body with one half-space collider through `at` with outward `normal`.
fn half_space(
    sys: &mut System,
    name: &str,
    normal: Vector3<f64>,
    at: Vector3<f64>,
    mat: ContactMaterial,
) -> anyhow::Result<BodyHandle> {
    Ok(sys.add_body(RigidBodyBuilder::fixed().name(name).collider(
        Shape::HalfSpace { normal },
        Isometry3::translation(at.x, at.y, at.z),
        mat,
    ))?)
}

/// The NSC solver named by the `solver` parameter.
pub(super) fn solver(
    name: &str,
    tolerance: f64,
    max_iterations: usize,
) -> anyhow::Result<Box<dyn chrono_ccp::CcpSolver>> {
    let settings = chrono_ccp::SolverSettings {
        tolerance,
        max_iterations,
        record_history: false,
    };
    Ok(match name {
        "apgd" => Box::new(chrono_ccp::Apgd::new(settings)),
        "bb" => Box::new(chrono_ccp::BarzilaiBorwein::new(settings)),
        "psor" => Box::new(chrono_ccp::Psor::new(settings)),
        other => anyhow::bail!("parameter `solver` must be `apgd`, `bb` or `psor`, got `{other}`"),
    })
}

/// Settle a bed behind the gates, open them and return the heap left on the plate after
/// `t_discharge`, for one method, rolling friction `mu_r` and packing `seed`.
pub(super) fn heap(
    p: &ReposeParams,
    method: ContactMethod,
    mu_r: f64,
    seed: u64,
    ctx: &RunContext,
    progress: (usize, usize),
) -> anyhow::Result<Heap> {
    let start = std::time::Instant::now();
    let d = p.grain_diameter;
    let r = 0.5 * d;
    let (half, w) = (0.5 * p.plate_width * d, p.thickness * d);
    let settings = SystemSettings {
        envelope: 0.05 * d,
        rolling_model: p.rolling_model,
        ..SystemSettings::default()
    };
    let mut sys = make_system(method, settings, p.tolerance, p.max_iterations)?;
    sys.set_solver(solver(&p.solver, p.tolerance, p.max_iterations)?);
    let mat = ContactMaterial::smc(p.young, 0.3, p.restitution, p.mu).with_rolling_friction(mu_r);
    mat.validate()?;
    // Walls, plate and gates impose their own friction on the grains (Zhou et al.'s mu_pw).
    let wall = ContactFriction {
        friction: p.wall_mu.unwrap_or(p.mu),
        rolling_friction: p.wall_rolling_friction.unwrap_or(mu_r),
        spinning_friction: 0.0,
    };
    // The slot's two walls and, 30 d down, the floor where discharged grains are parked.
    let z_park = -30.0 * d;
    let front = half_space(&mut sys, "front wall", Vector3::y(), Vector3::zeros(), mat)?;
    let back = half_space(
        &mut sys,
        "back wall",
        -Vector3::y(),
        Vector3::new(0.0, w, 0.0),
        mat,
    )?;
    half_space(
        &mut sys,
        "park floor",
        Vector3::z(),
        Vector3::new(0.0, 0.0, z_park),
        mat,
    )?;
    let plate = sys.add_body(RigidBodyBuilder::fixed().name("plate").collider(
        Shape::Box {
            half_extents: Vector3::new(half, 0.5 * w, r),
        },
        Isometry3::translation(0.0, 0.5 * w, -r),
        mat,
    ))?;
    let base_top = if p.rough_base { d } else { 0.0 };
    if p.rough_base {
        // Touching spheres of diameter d on the plate, one fixed body.
        let (nx, ny) = ((2.0 * half / d).floor() as usize, (w / d).floor() as usize);
        let mut base = RigidBodyBuilder::fixed().name("rough base");
        for i in 0..nx {
            for j in 0..ny {
                let x = -half + r + i as f64 * d;
                let y = r + j as f64 * d + 0.5 * (w - ny as f64 * d);
                base = base.collider(
                    Shape::Sphere { radius: r },
                    Isometry3::translation(x, y, r),
                    mat,
                );
            }
        }
        sys.add_body(base)?;
    }
    let gates = [
        half_space(
            &mut sys,
            "left gate",
            Vector3::x(),
            Vector3::new(-half, 0.0, 0.0),
            mat,
        )?,
        half_space(
            &mut sys,
            "right gate",
            -Vector3::x(),
            Vector3::new(half, 0.0, 0.0),
            mat,
        )?,
    ];
    for b in [front, back, plate, gates[0], gates[1]] {
        sys.set_contact_friction(b, Some(wall))?;
    }
    // A loose jittered lattice (sites 1.25 d apart) settles to a solid fraction ~0.6: the
    // grain count of the target bed at 0.58, the lattice region tall enough to hold them.
    let v_grain = std::f64::consts::PI / 6.0 * (0.975 * d).powi(3);
    let count = (0.58 * 2.0 * half * w * p.bed_height * d / v_grain).round() as usize;
    let spec = GrainBed {
        count: Some(count),
        seed,
        // Random horizontal velocities break the lattice's columns (see granular-hopper).
        kick: Some(Kick {
            speed: 0.1,
            salt: 0x5851_f42d_4c95_7f2d,
        }),
        ..GrainBed::new(
            Region::Box {
                lower: Vector3::new(-half, 0.0, base_top),
                upper: Vector3::new(half, w, base_top + 4.0 * p.bed_height * d),
            },
            0.95 * r,
            r,
            p.density,
            mat,
        )
    };
    let bed = spec.pour(&mut sys).map_err(|e| {
        anyhow::anyhow!("granular-repose: {e} (bed_height too large for the region)")
    })?;
    let handles = bed.handles.clone();
    let h = super::step_size(p.h, method, &sys);
    let n_settle = (p.t_settle / h).round() as u64;
    let n = n_settle + (p.t_discharge / h).round().max(1.0) as u64;
    let mut vtk = grain_frames(ctx, (0.02 / h).round() as u64)?;
    let mut parked = vec![false; handles.len()];
    let mut n_parked = 0usize;
    let rows = ((w / (1.5 * d)).floor() as usize).max(1);
    // Park the grains that left the plate: at rest on the floor, 1.5 d apart in rows
    // beyond the plate's end, touching nothing but the floor.
    let mut park = |sys: &mut System, i: u64| -> anyhow::Result<()> {
        record_grains(&mut vtk, i, sys)?;
        for (k, &b) in handles.iter().enumerate() {
            if parked[k] || sys.body(b)?.position().z > -2.0 * d {
                continue;
            }
            let (col, row) = (n_parked / rows, n_parked % rows);
            let at = Vector3::new(
                half + 10.0 * d + 1.5 * d * col as f64,
                (row as f64 + 0.5) * w / rows as f64,
                z_park + 1.01 * r,
            );
            let body = sys.body_mut(b)?;
            body.set_pose(at, UnitQuaternion::identity())?;
            body.set_linear_velocity(Vector3::zeros())?;
            body.set_angular_velocity(Vector3::zeros())?;
            parked[k] = true;
            n_parked += 1;
        }
        let (j, m) = progress;
        ctx.progress((j as f64 + i as f64 / n as f64) / m as f64);
        Ok(())
    };
    GrainBed {
        settle: Settle::Steps(n_settle),
        ..spec
    }
    .settle(&mut sys, &bed, h, &mut park)?;
    // Open the gates: move them 100 m outwards, out of the scene.
    for (g, s) in gates.iter().zip([-1.0, 1.0]) {
        sys.body_mut(*g)?.set_pose(
            Vector3::new(100.0 * s, 0.0, 0.0),
            UnitQuaternion::identity(),
        )?;
    }
    for i in n_settle + 1..=n {
        sys.step(h)?;
        park(&mut sys, i)?;
    }
    vtk.finish()?;
    let g = sys.settings().gravity.norm();
    let (mut points, mut ke, mut mass) = (Vec::new(), 0.0, 0.0);
    for (k, &b) in handles.iter().enumerate() {
        if parked[k] {
            continue;
        }
        let body = sys.body(b)?;
        let x = body.position();
        points.push((x.x, x.z));
        ke += body.kinetic_energy();
        mass += body.mass();
    }
    let on_plate = points.len();
    anyhow::ensure!(
        on_plate > 0,
        "granular-repose: no grain is left on the plate (mu = {}, mu_r = {mu_r})",
        p.mu
    );
    let mean_mass = mass / on_plate as f64;
    let bins = p.plate_width.round() as usize;
    let profile = heap_profile(&points, -half, 2.0 * half / bins as f64, bins);
    let (angle, flanks) = flank_angles(&profile, half).ok_or_else(|| {
        anyhow::anyhow!("granular-repose: too few surface columns on a flank to fit a slope")
    })?;
    Ok(Heap {
        angle,
        flanks,
        crest: points.iter().map(|q| q.1).fold(f64::MIN, f64::max),
        grains: handles.len(),
        on_plate,
        ke: ke / on_plate as f64 / (mean_mass * g * d),
        steps: n,
        wall_s: start.elapsed().as_secs_f64(),
        profile,
    })
}
