//! The hard case: a stack of 5 boxes, mass tripling per level (top 81x bottom), 4 corner
//! contacts per interface (statically indeterminate: N is singular), at rest under gravity.

mod common;

use chrono_ccp::{Apgd, CcpSolver, Psor, SolverSettings, TripletStep};
use common::{G, box_stack, check_complementarity};

const LEVELS: usize = 5;
const H: f64 = 0.01;
const TOL: f64 = 1e-6;

fn check(name: &str, solver: &mut dyn CcpSolver, max_iterations: usize) -> usize {
    let problem = box_stack(LEVELS, 0.5, H);
    solver.settings_mut().tolerance = TOL;
    solver.settings_mut().max_iterations = max_iterations;
    let mut gamma = vec![0.0; problem.n_rows()];
    let stats = solver.solve(&problem, &mut gamma);
    eprintln!("{name}: {} iterations, residual {:.3e}, converged {}", stats.iterations, stats.residual, stats.converged);
    assert!(stats.converged, "{name}: {stats:?}");
    // The answer: everything at rest, the ground carries the whole weight.
    check_complementarity(&problem, &gamma, 20.0 * TOL).unwrap();
    let mut v = vec![0.0; problem.ndof()];
    problem.velocities(&gamma, &mut v);
    let vmax = v.iter().fold(0.0f64, |a, x| a.max(x.abs()));
    assert!(vmax < 20.0 * TOL, "{name}: max |v+| = {vmax:e}");
    let total_weight: f64 = (0..LEVELS).map(|i| 3f64.powi(i as i32) * G * H).sum();
    let ground: f64 = (0..4).map(|c| gamma[3 * c]).sum();
    assert!((ground - total_weight).abs() < 1e-4 * total_weight, "{name}: ground {ground} vs {total_weight}");
    stats.iterations
}

fn settings() -> SolverSettings {
    SolverSettings::default()
}

#[test]
fn psor_reaches_tolerance_on_the_stack() {
    check("psor", &mut Psor::new(settings()), 2000);
}

#[test]
fn psor_variants_on_the_stack() {
    check("psor average step", &mut Psor::new(settings()).with_triplet_step(TripletStep::Average), 5000);
    check("psor symmetric", &mut Psor::new(settings()).with_symmetric(true), 5000);
    check("psor omega 1.3", &mut Psor::new(settings()).with_omega(1.3), 5000);
}

#[test]
fn apgd_reaches_tolerance_on_the_stack() {
    check("apgd", &mut Apgd::new(settings()), 2000);
}

#[test]
fn apgd_variants_on_the_stack() {
    check("apgd unpreconditioned", &mut Apgd::new(settings()).with_preconditioning(false), 5000);
    check("apgd no restart", &mut Apgd::new(settings()).with_adaptive_restart(false), 5000);
}
