//! Tests that can fail: the Jacobian against finite differences, a column at rest, the
//! hydrostatic pressure, the free-surface treatment, bad input and non-finite state.

use chrono_core::descriptor::{CcpProblem, ConstraintRows, SolverSettings, Variables};
use chrono_core::item::{PhysicsItem, StepContext};
use chrono_core::math::Vector3;
use chrono_core::rng::Rng;
use chrono_core::{System, SystemSettings};

use crate::{CfluidSettings, ConstraintFluid, SurfaceMode, lattice_box, tank_markers, wall_layers};

fn ctx(h: f64, gravity: Vector3<f64>) -> StepContext {
    StepContext {
        h,
        time: 0.0,
        step: 0,
        gravity,
    }
}

/// A quasi-2D tank: fluid `[0, w] x [0, ly] x [0, depth]`, periodic along y, walls at
/// x-, x+, z-.
fn tank(dp: f64, w: f64, depth: f64, surface: SurfaceMode) -> ConstraintFluid {
    tank_with(dp, w, depth, surface, false, false)
}

/// [`tank`] with or without wall-marker rows and the surface reference.
fn tank_with(
    dp: f64,
    w: f64,
    depth: f64,
    surface: SurfaceMode,
    wall_marker_rows: bool,
    surface_reference: bool,
) -> ConstraintFluid {
    let h_over_dp = 1.2;
    let layers = wall_layers(h_over_dp);
    let ly = 6.0 * dp;
    let t = layers as f64 * dp;
    let settings = CfluidSettings {
        spacing: dp,
        h_over_dp,
        surface,
        wall_marker_rows,
        surface_reference,
        domain_lower: [-t, 0.0, -t],
        domain_upper: [w + t, ly, 2.0 * depth],
        periodic: [false, true, false],
        ..CfluidSettings::default()
    };
    let (lo, hi) = ([0.0, 0.0, 0.0], [w, ly, depth]);
    let fluid = lattice_box(lo, hi, dp).unwrap();
    let mut top = hi;
    top[2] = 2.0 * depth;
    let walls = tank_markers(lo, top, dp, layers, [true, true, false, false, true, false]).unwrap();
    ConstraintFluid::new("water", settings, &fluid, &walls).unwrap()
}

fn system(tolerance: f64) -> System {
    let solver = chrono_ccp::Apgd::new(SolverSettings {
        tolerance,
        max_iterations: 2000,
        record_history: false,
    });
    System::new(SystemSettings::default(), Box::new(solver)).unwrap()
}

#[test]
fn jacobian_matches_finite_differences() {
    jacobian_check(false);
}

/// The wall markers' own rows (`wall_marker_rows`) against central differences of the
/// markers' densities along the same fluid velocity fields, and the fluid rows with them.
#[test]
fn wall_marker_rows_match_finite_differences() {
    jacobian_check(true);
}

fn jacobian_check(wall_marker_rows: bool) {
    let dp = 0.01;
    let mut rng = Rng::new(7);
    let settings = CfluidSettings {
        wall_marker_rows,
        spacing: dp,
        domain_lower: [-0.05, 0.0, -0.05],
        domain_upper: [0.1, 0.08, 0.1],
        periodic: [false, true, false],
        ..CfluidSettings::default()
    };
    // a jittered 4 x 8 x 4 block (periodic along y) above one wall layer
    let mut fluid = lattice_box([0.0; 3], [0.04, 0.08, 0.04], dp).unwrap();
    for p in &mut fluid {
        for c in p.iter_mut() {
            *c += 0.2 * dp * rng.range(-1.0, 1.0);
        }
    }
    let walls = tank_markers(
        [0.0; 3],
        [0.04, 0.08, 0.04],
        dp,
        1,
        [false, false, false, false, true, false],
    )
    .unwrap();
    let n = fluid.len();
    let mut item = ConstraintFluid::new("fd", settings.clone(), &fluid, &walls).unwrap();
    let mut vars = Variables::new();
    item.add_variables(&mut vars);
    let mut rows = ConstraintRows::new();
    let c = ctx(1e-3, Vector3::zeros());
    item.add_constraints(&c, &vars, &mut rows).unwrap();
    let mut problem = CcpProblem::new();
    problem
        .assemble(&vars, &rows, &vec![0.0; vars.ndof()])
        .unwrap();
    let rho_0 = settings.rest_density;
    for trial in 0..3 {
        let v: Vec<f64> = (0..3 * n).map(|_| rng.range(-1.0, 1.0)).collect();
        let delta = 1e-7;
        let shifted = |s: f64| {
            let pts: Vec<[f64; 3]> = fluid
                .iter()
                .enumerate()
                .map(|(i, p)| std::array::from_fn(|a| p[a] + s * delta * v[3 * i + a]))
                .collect();
            let mut it = ConstraintFluid::new("fd", settings.clone(), &pts, &walls).unwrap();
            let mut rho = it.compute_densities().unwrap().to_vec();
            rho.extend_from_slice(it.wall_densities());
            rho
        };
        let (plus, minus) = (shifted(1.0), shifted(-1.0));
        let mut worst = 0.0f64;
        let mut scale = 0.0f64;
        for i in 0..n {
            let dc = (plus[i] - minus[i]) / (2.0 * delta * rho_0);
            let row = problem.row_index(item.row_ids()[i]);
            // rows are D_i = -grad C_i
            let jv = -problem.row_dot(row, &v);
            worst = worst.max((jv - dc).abs());
            scale = scale.max(dc.abs());
        }
        if wall_marker_rows {
            assert!(
                item.wall_row_ids().len() >= 32,
                "{} wall rows: the markers under the block have fluid neighbours",
                item.wall_row_ids().len()
            );
            for (k, id) in item.wall_row_ids() {
                let k = n + *k as usize;
                let dc = (plus[k] - minus[k]) / (2.0 * delta * rho_0);
                let jv = -problem.row_dot(problem.row_index(*id), &v);
                worst = worst.max((jv - dc).abs());
                scale = scale.max(dc.abs());
            }
        } else {
            assert!(item.wall_row_ids().is_empty());
        }
        assert!(
            scale > 1.0,
            "trial {trial}: the test moves nothing ({scale})"
        );
        assert!(
            worst < 1e-6 * scale,
            "trial {trial}: Jacobian off by {worst} (scale {scale})"
        );
    }
}

#[test]
fn column_at_rest_keeps_density_and_pressure_is_hydrostatic() {
    let (dp, w, depth) = (0.01, 0.06, 0.12);
    let item = tank(dp, w, depth, SurfaceMode::OneSided);
    let mut sys = system(1e-6);
    let id = sys.add_item(Box::new(item));
    let h = 2e-3;
    let tol = 2e-3;
    let mut worst = 0.0f64;
    let mut ke_peak = 0.0f64;
    let (steps, averaged) = (250, 100);
    let mut p_mean = Vec::new();
    for step in 0..steps {
        sys.step(h).unwrap();
        let f = sys.item::<ConstraintFluid>(id).unwrap();
        worst = worst.max(f.max_compression());
        ke_peak = ke_peak.max(f.kinetic_energy());
        // the pressure of one step carries the settling oscillation: average the last steps
        if step >= steps - averaged {
            p_mean.resize(f.n_fluid(), 0.0);
            for (i, pm) in p_mean.iter_mut().enumerate() {
                *pm += f.pressure(i) / averaged as f64;
            }
        }
    }
    let f = sys.item_mut::<ConstraintFluid>(id).unwrap();
    f.compute_densities().unwrap();
    let end = f.max_compression();
    assert!(worst < tol, "max compression during the run {worst}");
    assert!(end < tol, "max compression at the end {end}");
    // settling: the surface layers (whose support is not full) sink a fraction of dp
    // until the rows below carry them, then XSPH damps the motion
    let ke = f.kinetic_energy();
    assert!(
        ke < 0.25 * ke_peak,
        "not settling: KE {ke} J, peak {ke_peak} J"
    );
    let m_total = f.particle_mass() * f.n_fluid() as f64;
    assert!(
        ke / m_total < 1e-3,
        "specific kinetic energy {} J/kg",
        ke / m_total
    );
    for i in 0..f.n_fluid() {
        let p = f.position(i);
        assert!(
            p[0] > -0.5 * dp && p[0] < w + 0.5 * dp && p[2] > -0.5 * dp,
            "particle {i} left the tank: {p:?}"
        );
    }
    // pressure against depth in the bulk: away from the walls (a wall marker has no row,
    // so it acts as a neighbour of zero pressure and the first fluid layers carry about
    // twice the pressure), below the surface layers whose support is not full
    let support = f.kernel().support();
    let (mut zs, mut ps) = (Vec::new(), Vec::new());
    for i in 0..f.n_fluid() {
        let p = f.position(i);
        if p[0] > support && p[0] < w - support && p[2] > support && p[2] < depth - support {
            zs.push(p[2]);
            ps.push(p_mean[i]);
        }
    }
    let n = zs.len() as f64;
    assert!(n > 10.0);
    let (mz, mp) = (zs.iter().sum::<f64>() / n, ps.iter().sum::<f64>() / n);
    let sxy: f64 = zs.iter().zip(&ps).map(|(z, p)| (z - mz) * (p - mp)).sum();
    let sxx: f64 = zs.iter().map(|z| (z - mz) * (z - mz)).sum();
    let syy: f64 = ps.iter().map(|p| (p - mp) * (p - mp)).sum();
    let slope = sxy / sxx;
    let r2 = sxy * sxy / (sxx * syy);
    let expected = 1000.0 * chrono_core::math::GRAVITY.z;
    eprintln!(
        "column: max compression {worst:.3e} (run), {end:.3e} (end); KE {ke:.3e} J \
         (peak {ke_peak:.3e}); dp/dz = {slope:.1} Pa/m (expected {expected}), R^2 = {r2:.4}"
    );
    assert!(
        (slope / expected - 1.0).abs() < 0.1,
        "dp/dz = {slope} Pa/m, expected {expected}"
    );
    assert!(r2 > 0.95, "pressure is not linear in depth: R^2 = {r2}");
    assert!(ps.iter().all(|p| *p > 0.0), "negative bulk pressure");
}

/// The mean height change of the top lattice layer (dp units) and the fluid's centre of
/// mass (m) of a column at rest after `steps` of 2 ms, with or without
/// [`CfluidSettings::surface_reference`].
fn top_layer_sinking(surface_reference: bool, steps: usize) -> (f64, f64) {
    let (dp, w, depth) = (0.01, 0.06, 0.12);
    let item = tank_with(
        dp,
        w,
        depth,
        SurfaceMode::OneSided,
        false,
        surface_reference,
    );
    let n = item.n_fluid();
    let per_layer = n / (depth / dp).round() as usize;
    let mean_z = |f: &ConstraintFluid, r: std::ops::Range<usize>| {
        let k = r.len() as f64;
        r.map(|i| f.position(i)[2]).sum::<f64>() / k
    };
    let (top0, com0) = (mean_z(&item, n - per_layer..n), mean_z(&item, 0..n));
    let mut sys = system(1e-6);
    let id = sys.add_item(Box::new(item));
    for _ in 0..steps {
        sys.step(2e-3).unwrap();
    }
    let f = sys.item::<ConstraintFluid>(id).unwrap();
    let (top, com) = (mean_z(f, n - per_layer..n), mean_z(f, 0..n));
    ((top - top0) / dp, com - com0)
}

#[test]
fn the_surface_reference_halves_the_surface_packing() {
    let (plain, com_plain) = top_layer_sinking(false, 150);
    let (refd, com_refd) = top_layer_sinking(true, 150);
    eprintln!(
        "top layer shift (dp): plain {plain:.3}, surface reference {refd:.3}; \
         centre of mass (m): {com_plain:.2e}, {com_refd:.2e}"
    );
    // measured: plain -0.51 dp and -1.8 mm, with the reference -0.29 dp and -0.84 mm
    // (the rest is the bulk's compaction, see docs/validation-cfluid.md)
    assert!(
        plain < -0.3,
        "plain rows: the top layer sank by {plain} dp only"
    );
    assert!(
        refd.abs() < 0.7 * plain.abs() && com_refd.abs() < 0.6 * com_plain.abs(),
        "surface reference: top layer {refd} dp, centre of mass {com_refd} m"
    );
}

/// A loose cloud (every particle below rho_0) in zero gravity, expanding.
fn expanding_cloud(surface: SurfaceMode) -> (f64, f64) {
    let dp = 0.01;
    let settings = CfluidSettings {
        spacing: dp,
        surface,
        domain_lower: [-0.2; 3],
        domain_upper: [0.2; 3],
        ..CfluidSettings::default()
    };
    let fluid: Vec<[f64; 3]> = lattice_box([0.0; 3], [0.05; 3], dp)
        .unwrap()
        .into_iter()
        .map(|p| p.map(|c| 1.2 * c))
        .collect();
    let v0: Vec<[f64; 3]> = fluid.iter().map(|p| p.map(|c| c - 0.03)).collect();
    let mut item = ConstraintFluid::new("cloud", settings, &fluid, &[]).unwrap();
    item.set_velocities(&v0).unwrap();
    let before = item.kinetic_energy();
    let mut sys = system(1e-8);
    let mut s = sys.settings().clone();
    s.gravity = Vector3::zeros();
    sys.set_settings(s).unwrap();
    let id = sys.add_item(Box::new(item));
    sys.step(1e-3).unwrap();
    let f = sys.item::<ConstraintFluid>(id).unwrap();
    assert!(f.densities().iter().all(|r| *r < 1000.0));
    let max_g = f.impulses().iter().fold(0.0f64, |m, g| m.max(g.abs()));
    (f.kinetic_energy() / before, max_g)
}

#[test]
fn free_surface_particles_do_not_pull() {
    for mode in [SurfaceMode::OneSided, SurfaceMode::Unilateral] {
        let (ke_ratio, max_g) = expanding_cloud(mode);
        assert_eq!(max_g, 0.0, "{mode:?}: a loose cloud got impulses");
        // XSPH only smooths a linear velocity field slightly
        assert!(
            ke_ratio > 0.9,
            "{mode:?}: expansion slowed, KE ratio {ke_ratio}"
        );
    }
    // the clamped bilateral variant holds the density rate at zero: it resists
    let (ke_ratio, max_g) = expanding_cloud(SurfaceMode::Clamped);
    assert!(
        max_g > 0.0 && ke_ratio < 0.5,
        "clamped: KE ratio {ke_ratio}, max |g| {max_g}"
    );
}

#[test]
fn bad_input_names_the_field() {
    let bad = |s: CfluidSettings| {
        ConstraintFluid::new("x", s, &[[0.5; 3]], &[])
            .err()
            .expect("accepted")
            .to_string()
    };
    let e = bad(CfluidSettings {
        rest_density: -1.0,
        ..Default::default()
    });
    assert!(e.contains("cfluid.rest_density"), "{e}");
    let e = bad(CfluidSettings {
        xsph: 2.0,
        ..Default::default()
    });
    assert!(e.contains("cfluid.xsph"), "{e}");
    let e = bad(CfluidSettings {
        compressibility: f64::NAN,
        ..Default::default()
    });
    assert!(e.contains("cfluid.compressibility"), "{e}");
    let e = bad(CfluidSettings {
        domain_upper: [1.0, -1.0, 1.0],
        ..Default::default()
    });
    assert!(e.contains("cfluid.domain_upper[1]"), "{e}");
    let e = ConstraintFluid::new(
        "x",
        CfluidSettings::default(),
        &[[0.5; 3], [0.1, f64::NAN, 0.0]],
        &[],
    )
    .err()
    .unwrap()
    .to_string();
    assert!(e.contains("fluid[1][1]"), "{e}");
    let e = ConstraintFluid::new("x", CfluidSettings::default(), &[], &[])
        .err()
        .unwrap()
        .to_string();
    assert!(e.contains("fluid"), "{e}");
    let mut f = ConstraintFluid::new("x", CfluidSettings::default(), &[[0.5; 3]], &[]).unwrap();
    let e = f
        .set_velocities(&[[0.0, 0.0, f64::INFINITY]])
        .unwrap_err()
        .to_string();
    assert!(e.contains("velocities[0][2]"), "{e}");
}

#[test]
fn non_finite_state_names_item_and_step() {
    let mut f = ConstraintFluid::new(
        "puddle",
        CfluidSettings::default(),
        &[[0.5; 3], [0.51, 0.5, 0.5]],
        &[],
    )
    .unwrap();
    let mut vars = Variables::new();
    f.add_variables(&mut vars);
    let mut rows = ConstraintRows::new();
    let mut c = ctx(1e-3, Vector3::zeros());
    c.step = 42;
    f.add_constraints(&c, &vars, &mut rows).unwrap();
    let mut problem = CcpProblem::new();
    problem.assemble(&vars, &rows, &[0.0; 6]).unwrap();
    let v = [0.0, 0.0, 0.0, f64::NAN, 0.0, 0.0];
    let e = f
        .update(&c, &vars, &v, &problem, &[0.0; 2])
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("puddle") && e.contains("particle 1") && e.contains("step 42"),
        "{e}"
    );
}

/// A collapsing column at a large step (`h v / h_k ~ 0.4`): without the position
/// projection the drift of one step compresses the fluid by several tenths of a percent;
/// with it the worst compression at the start of every step stays at the projection's
/// tolerance, and the projection reports its sweeps.
#[test]
fn position_projection_removes_the_drift_of_a_large_step() {
    let dp = 0.01;
    let h_over_dp = 1.2;
    let layers = wall_layers(h_over_dp);
    let (len, ly, depth) = (0.2, 6.0 * dp, 0.12);
    let t = layers as f64 * dp;
    let worst = |iterations: u32| {
        let settings = CfluidSettings {
            spacing: dp,
            h_over_dp,
            position_iterations: iterations,
            position_tolerance: 2e-4,
            domain_lower: [-t, 0.0, -t],
            domain_upper: [len + t, ly, 2.0 * depth],
            periodic: [false, true, false],
            ..CfluidSettings::default()
        };
        let fluid = lattice_box([0.0; 3], [0.06, ly, depth], dp).unwrap();
        let walls = tank_markers(
            [0.0; 3],
            [len, ly, 2.0 * depth],
            dp,
            layers,
            [true, true, false, false, true, false],
        )
        .unwrap();
        let item = ConstraintFluid::new("water", settings, &fluid, &walls).unwrap();
        let mut sys = system(1e-4);
        let id = sys.add_item(Box::new(item));
        let (mut worst, mut sweeps) = (0.0f64, 0u32);
        for _ in 0..25 {
            sys.step(6e-3).unwrap();
            let f = sys.item::<ConstraintFluid>(id).unwrap();
            worst = worst.max(f.max_compression());
            sweeps += f.last_projection().0;
        }
        (worst, sweeps)
    };
    let (off, none) = worst(0);
    let (on, sweeps) = worst(100);
    assert_eq!(none, 0);
    assert!(sweeps > 0, "the projection never ran");
    assert!(off > 2e-3, "no drift to remove: {off}");
    assert!(
        on <= 2.5e-4,
        "projected: worst compression {on} (off: {off})"
    );
}

/// A column at rest (6 x 6 x 12 at dp = 1 cm, 0.5 s at h = 2 ms): the pressure of the
/// first fluid layer on the floor, averaged over the last 0.2 s and over the particles
/// away from the side walls, over the bulk's linear fit of pressure against depth
/// extrapolated to that layer's height; and that layer's mean height over `dp`.
fn floor_layer_pressure_ratio(wall_marker_rows: bool) -> (f64, f64) {
    let (dp, w, depth) = (0.01, 0.06, 0.12);
    let item = tank_with(dp, w, depth, SurfaceMode::OneSided, wall_marker_rows, false);
    let mut sys = system(1e-6);
    let id = sys.add_item(Box::new(item));
    let (steps, averaged) = (250, 100);
    let mut p_mean = Vec::new();
    for step in 0..steps {
        sys.step(2e-3).unwrap();
        let f = sys.item::<ConstraintFluid>(id).unwrap();
        if step >= steps - averaged {
            p_mean.resize(f.n_fluid(), 0.0);
            for (i, pm) in p_mean.iter_mut().enumerate() {
                *pm += f.pressure(i) / averaged as f64;
            }
        }
    }
    let f = sys.item::<ConstraintFluid>(id).unwrap();
    let support = f.kernel().support();
    let (mut zs, mut ps, mut first) = (Vec::new(), Vec::new(), Vec::new());
    for i in 0..f.n_fluid() {
        let p = f.position(i);
        if p[0] > support && p[0] < w - support {
            if p[2] < dp {
                first.push((p[2], p_mean[i]));
            } else if p[2] > support && p[2] < depth - support {
                zs.push(p[2]);
                ps.push(p_mean[i]);
            }
        }
    }
    assert!(zs.len() > 10 && !first.is_empty());
    let n = zs.len() as f64;
    let (mz, mp) = (zs.iter().sum::<f64>() / n, ps.iter().sum::<f64>() / n);
    let sxy: f64 = zs.iter().zip(&ps).map(|(z, p)| (z - mz) * (p - mp)).sum();
    let sxx: f64 = zs.iter().map(|z| (z - mz) * (z - mz)).sum();
    let slope = sxy / sxx;
    let m = first.len() as f64;
    let z1 = first.iter().map(|f| f.0).sum::<f64>() / m;
    let p1 = first.iter().map(|f| f.1).sum::<f64>() / m;
    let ratio = p1 / (mp + slope * (z1 - mz));
    eprintln!(
        "wall rows {wall_marker_rows}: floor layer at z = {z1:.4} m, p = {p1:.1} Pa, \
         bulk fit there {:.1} Pa, ratio {ratio:.3}",
        mp + slope * (z1 - mz)
    );
    (ratio, z1 / dp)
}

/// Without rows of their own, the floor's markers are neighbours of zero pressure in the
/// symmetric pair forces, so the first layer carries about twice the hydrostatic
/// pressure; with `wall_marker_rows` the markers carry the pressure and the first layer's
/// pressure continues the bulk's hydrostatic profile. The rows also keep the first layer
/// where the lattice put it, `dp / 2` above the floor face: without them (and without
/// colliders behind the markers) it sinks toward the markers.
#[test]
fn wall_marker_rows_carry_the_floor_pressure() {
    let (with, z_with) = floor_layer_pressure_ratio(true);
    let (without, z_without) = floor_layer_pressure_ratio(false);
    assert!(
        z_with > 0.4 && z_without < 0.35,
        "floor layer at {z_with} dp with wall rows, {z_without} dp without"
    );
    assert!(
        (with - 1.0).abs() < 0.15,
        "with wall rows: floor layer at {with} x the bulk's profile"
    );
    assert!(
        without > 1.5,
        "without wall rows: floor layer at {without} x the bulk's profile (expected ~2)"
    );
}

/// The largest and the RMS deviation from the shear `v_x = s z` after one step of a fluid block
/// (periodic in x and y, free top and bottom, no gravity) sheared at `s`, with XSPH 0.1,
/// plain or gradient-corrected; and the same for a noisy shear (`noise` m/s on top).
fn sheared_block(corrected: bool, noise: f64) -> (f64, f64) {
    let dp = 0.01;
    let l = 0.06;
    let settings = CfluidSettings {
        spacing: dp,
        xsph: 0.1,
        xsph_corrected: corrected,
        domain_lower: [0.0, 0.0, -0.1],
        domain_upper: [l, l, 0.2],
        periodic: [true, true, false],
        ..CfluidSettings::default()
    };
    let fluid = lattice_box([0.0; 3], [l, l, 0.06], dp).unwrap();
    let s = 2.0;
    let mut rng = Rng::new(7);
    let v0: Vec<[f64; 3]> = fluid
        .iter()
        .map(|p| [s * p[2] + noise * (2.0 * rng.uniform() - 1.0), 0.0, 0.0])
        .collect();
    let mut item = ConstraintFluid::new("shear", settings, &fluid, &[]).unwrap();
    item.set_velocities(&v0).unwrap();
    let mut sys = system(1e-10);
    let mut st = sys.settings().clone();
    st.gravity = Vector3::zeros();
    sys.set_settings(st).unwrap();
    let id = sys.add_item(Box::new(item));
    sys.step(1e-4).unwrap();
    let f = sys.item::<ConstraintFluid>(id).unwrap();
    let dev: Vec<f64> = f
        .velocities()
        .iter()
        .zip(&fluid)
        .map(|(v, p)| (v[0] - s * p[2]).abs())
        .collect();
    let rms = (dev.iter().map(|d| d * d).sum::<f64>() / dev.len() as f64).sqrt();
    (dev.iter().copied().fold(0.0, f64::max), rms)
}

/// The gradient-corrected XSPH leaves a linear velocity field alone at a free surface
/// (plain XSPH drags the surface layers toward their one-sided mean), and still smooths
/// particle noise.
#[test]
fn corrected_xsph_keeps_a_linear_field_and_damps_noise() {
    let plain = sheared_block(false, 0.0).0;
    let corrected = sheared_block(true, 0.0).0;
    // plain: the top layer moves by ~ eps (sum of one-sided weights) s dp / 2 ~ 1e-4 m/s
    assert!(plain > 2e-4, "plain XSPH on a shear: {plain}");
    assert!(corrected < 1e-6, "corrected XSPH on a shear: {corrected}");
    // uniform noise of +-0.01 m/s (RMS 0.00577): smoothed by both, by a similar amount
    let (_, rms_c) = sheared_block(true, 0.01);
    let (_, rms_p) = sheared_block(false, 0.01);
    assert!(
        rms_c < 0.95 * 0.01 / 3f64.sqrt(),
        "corrected XSPH on noise: RMS {rms_c}"
    );
    assert!(
        rms_c < 1.1 * rms_p,
        "corrected {rms_c} against plain {rms_p}"
    );
}

/// `set_damping`: a uniform stream through a triply periodic box (no gravity: no row and
/// no smoothing acts on it) decays as `exp(-k t)` exactly per step; a negative rate is an
/// error naming `damping`.
#[test]
fn damping_relaxes_a_uniform_stream_at_its_rate() {
    let (dp, l) = (0.01, 0.06);
    let settings = CfluidSettings {
        spacing: dp,
        domain_lower: [0.0; 3],
        domain_upper: [l; 3],
        periodic: [true; 3],
        ..CfluidSettings::default()
    };
    let fluid = lattice_box([0.0; 3], [l; 3], dp).unwrap();
    let mut item = ConstraintFluid::new("stream", settings, &fluid, &[]).unwrap();
    item.set_velocities(&vec![[0.2, -0.1, 0.05]; fluid.len()])
        .unwrap();
    let e = item.set_damping(-1.0).unwrap_err().to_string();
    assert!(e.contains("damping"), "{e}");
    let k = 8.0;
    item.set_damping(k).unwrap();
    assert_eq!(item.damping(), k);
    let mut sys = system(1e-10);
    let mut st = sys.settings().clone();
    st.gravity = Vector3::zeros();
    sys.set_settings(st).unwrap();
    let id = sys.add_item(Box::new(item));
    let (h, n) = (2e-3, 25);
    for _ in 0..n {
        sys.step(h).unwrap();
    }
    let f = sys.item::<ConstraintFluid>(id).unwrap();
    let expect = (-k * h * n as f64).exp();
    for v in f.velocities() {
        for (a, v0) in [0.2, -0.1, 0.05].iter().enumerate() {
            assert!(
                (v[a] / v0 - expect).abs() < 1e-9,
                "{} against {expect}",
                v[a] / v0
            );
        }
    }
}
