//! The hard case: a stack of 5 boxes, mass tripling per level (top 81x bottom), 4 corner
//! contacts per interface (statically indeterminate: N is singular), at rest under gravity.

use chrono_ccp::testing::{box_stack, box_stack_ratio, check_complementarity};
use chrono_ccp::{Admm, Apgd, CcpSolver, Psor, SolverSettings, TripletStep};
use chrono_core::math::GRAVITY;

const LEVELS: usize = 5;
const H: f64 = 0.01;
const TOL: f64 = 1e-6;

fn check(name: &str, solver: &mut dyn CcpSolver, max_iterations: usize) -> usize {
    let problem = box_stack(LEVELS, 0.5, H).unwrap();
    solver.settings_mut().tolerance = TOL;
    solver.settings_mut().max_iterations = max_iterations;
    let mut gamma = vec![0.0; problem.n_rows()];
    let stats = solver.solve(&problem, &mut gamma);
    eprintln!(
        "{name}: {} iterations, residual {:.3e}, converged {}",
        stats.iterations, stats.residual, stats.converged
    );
    assert!(stats.converged, "{name}: {stats:?}");
    // The answer: everything at rest, the ground carries the whole weight.
    check_complementarity(&problem, &gamma, 20.0 * TOL).unwrap();
    let mut v = vec![0.0; problem.ndof()];
    problem.velocities(&gamma, &mut v);
    // The residual is an RMS over 60 rows of constraint velocities: a single row may be off by
    // sqrt(60) TOL ~ 8e-6 m/s, and body velocities are the constraint velocities mapped back
    // through the pseudo-inverse of D' (lever arms of 0.5 m amplify), so 1e-4 m/s is the bound.
    let vmax = v.iter().fold(0.0f64, |a, x| a.max(x.abs()));
    assert!(vmax < 100.0 * TOL, "{name}: max |v+| = {vmax:e}");
    let total_weight: f64 = (0..LEVELS)
        .map(|i| 3f64.powi(i as i32) * (-GRAVITY.z) * H)
        .sum();
    let ground: f64 = (0..4).map(|c| gamma[3 * c]).sum();
    assert!(
        (ground - total_weight).abs() < 1e-4 * total_weight,
        "{name}: ground {ground} vs {total_weight}"
    );
    stats.iterations
}

fn settings() -> SolverSettings {
    SolverSettings::default()
}

// Measured (forward PSOR, MaxEigen triplet step): ~69k sweeps to 1e-6; symmetric ~27k
// iterations; Chrono's averaged step ~55k. PSOR's rate degrades with the mass ratio (equal
// masses: ~2k sweeps; light on heavy: ~200). APGD: ~130 iterations (205 without the Jacobi
// metric, 614 without restart). The caps below leave ~40% headroom over those counts.

#[test]
fn psor_reaches_tolerance_on_the_stack() {
    let it = check(
        "psor",
        &mut Psor::new(settings()).with_check_every(10),
        100_000,
    );
    assert!(it <= 100_000);
}

#[test]
fn psor_variants_on_the_stack() {
    check(
        "psor symmetric",
        &mut Psor::new(settings()).with_symmetric(true),
        40_000,
    );
    check(
        "psor average step",
        &mut Psor::new(settings()).with_triplet_step(TripletStep::Average),
        80_000,
    );
}

#[test]
fn apgd_reaches_tolerance_on_the_stack() {
    check("apgd", &mut Apgd::new(settings()), 200);
}

#[test]
fn apgd_variants_on_the_stack() {
    check(
        "apgd unpreconditioned",
        &mut Apgd::new(settings()).with_preconditioning(false),
        300,
    );
    check(
        "apgd no restart",
        &mut Apgd::new(settings()).with_adaptive_restart(false),
        900,
    );
}

#[test]
fn warm_started_next_step_is_cheap() {
    // Solve, then solve the same stack again from that answer (a simulation at rest): the
    // warm start is already converged.
    let problem = box_stack(LEVELS, 0.5, H).unwrap();
    let solvers: Vec<Box<dyn CcpSolver>> = vec![
        Box::new(Psor::new(settings())),
        Box::new(Apgd::new(settings())),
    ];
    for mut s in solvers {
        s.settings_mut().max_iterations = 100_000;
        let mut gamma = vec![0.0; problem.n_rows()];
        assert!(s.solve(&problem, &mut gamma).converged);
        let warm = s.solve(&problem, &mut gamma);
        assert!(
            warm.converged && warm.iterations <= 1,
            "{}: {warm:?}",
            s.name()
        );
    }
}

#[test]
fn admm_reaches_tolerance_on_the_stack() {
    check("admm", &mut Admm::new(settings()), ADMM_CAP);
}

/// ADMM's iteration cap on the stack (16 measured; ~60% headroom).
const ADMM_CAP: usize = 25;

#[test]
fn admm_iterations_do_not_grow_with_the_mass_ratio() {
    // The property that makes ADMM the heavy-on-light path: its exact solve takes the
    // ill-conditioning of the mass ratio, so its iterations to the tolerance grow far less
    // from equal masses to a ratio of 10 per level (6 levels: top 1e5 x bottom) than
    // APGD's (measured: ADMM 8 -> 40, APGD 45 -> 2173).
    let mut counts = Vec::new();
    for ratio in [1.0, 3.0, 10.0] {
        let problem = box_stack_ratio(6, ratio, 0.5, H).unwrap();
        let mut s = Admm::new(settings())
            .with_tolerance(TOL)
            .with_max_iterations(10_000);
        let mut gamma = vec![0.0; problem.n_rows()];
        let stats = s.solve(&problem, &mut gamma);
        assert!(stats.converged, "ratio {ratio}: {stats:?}");
        check_complementarity(&problem, &gamma, 20.0 * TOL).unwrap();
        let mut a = Apgd::new(settings())
            .with_tolerance(TOL)
            .with_max_iterations(100_000);
        let mut ga = vec![0.0; problem.n_rows()];
        let sa = a.solve(&problem, &mut ga);
        assert!(sa.converged, "apgd at ratio {ratio}: {sa:?}");
        eprintln!(
            "ratio {ratio}: admm {} iterations ({} factorizations), apgd {}",
            stats.iterations,
            s.factorizations(),
            sa.iterations,
        );
        counts.push((stats.iterations as f64, sa.iterations as f64));
    }
    let admm_growth = counts[2].0 / counts[0].0;
    let apgd_growth = counts[2].1 / counts[0].1;
    assert!(
        4.0 * admm_growth < apgd_growth,
        "growth from ratio 1 to 10: admm {admm_growth:.1}x, apgd {apgd_growth:.1}x ({counts:?})"
    );
}

#[test]
fn admm_over_relaxation_reaches_plain_admms_answer() {
    // Over-relaxation (`AdmmOptions::relaxation`) changes the path, not the fixed point: on
    // the heavy stack (mass ratio 10 per level) and on random problems both forms converge
    // to the same objective and satisfy complementarity. (Iterations are not asserted: on
    // this stack 41 relaxed against 40 plain; on the vehicle's local blocks -39 %, why
    // `LocalDirect` relaxes its local solves, docs/validation-vehicle.md.)
    use chrono_ccp::AdmmOptions;
    use chrono_ccp::testing::{objective, random_problem};
    let solve = |problem: &chrono_core::descriptor::CcpProblem, relaxation: f64| {
        let mut s = Admm::new(settings())
            .with_tolerance(TOL)
            .with_max_iterations(10_000)
            .with_options(AdmmOptions {
                relaxation,
                ..AdmmOptions::default()
            });
        let mut g = vec![0.0; problem.n_rows()];
        let stats = s.solve(problem, &mut g);
        assert!(stats.converged, "relaxation {relaxation}: {stats:?}");
        check_complementarity(problem, &g, 20.0 * TOL).unwrap();
        (objective(problem, &g), stats.iterations)
    };
    let stack = box_stack_ratio(6, 10.0, 0.5, H).unwrap();
    let (f1, n1) = solve(&stack, 1.0);
    let (f16, n16) = solve(&stack, 1.6);
    assert!((f1 - f16).abs() <= 1e-6 * (1.0 + f1.abs()), "{f1} vs {f16}");
    eprintln!("stack: relaxed {n16} iterations, plain {n1}");
    for seed in 0..20 {
        let p = random_problem(seed).unwrap();
        let (a, _) = solve(&p, 1.0);
        let (b, _) = solve(&p, 1.6);
        assert!(
            (a - b).abs() <= 1e-6 * (1.0 + a.abs()),
            "seed {seed}: {a} vs {b}"
        );
    }
}

#[test]
#[should_panic(expected = "relaxation")]
fn admm_relaxation_outside_its_range_is_refused() {
    let _ = Admm::new(settings()).with_options(chrono_ccp::AdmmOptions {
        relaxation: 2.0,
        ..chrono_ccp::AdmmOptions::default()
    });
}
