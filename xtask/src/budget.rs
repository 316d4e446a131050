//! The time budget of a validation run.
//!
//! `cargo xtask validate` at its defaults must finish in at most [`DEFAULT_RUN_S`] (20
//! minutes) on the project's 2-core machine, and every later case lives within that rule:
//! each area has its share, each case its part of the share ([`BUDGETS`]). A case whose
//! complete set-up takes longer keeps it under `--full`. The budgets also serve the
//! progress estimate of the time left ([`crate::eta`]) on a machine that has no timings
//! of an earlier run.
//!
//! Wall seconds on 2 cores. `quick_s` is measured: the `--quick` run of 2026-12-03 plus
//! 10 %, rounded up (docs/performance.md, "Validation run time"; capped at the default where
//! a default is its quick set-up). `default_s` is measured too: the default run of 2026-12-03 on an
//! idle machine, rounded up (for the cases whose default became their quick set-up after
//! that run, their quick time); the headroom is [`PLANNED_FRACTION`].

use crate::case::Mode;

/// The limit of the default run, wall seconds on 2 cores.
pub const DEFAULT_RUN_S: f64 = 1200.0;

/// The part of [`DEFAULT_RUN_S`] the budgets may plan for: the rest is headroom for a
/// machine busier than the one measured.
pub const PLANNED_FRACTION: f64 = 0.9;

/// One case's budget: wall seconds at the defaults and under `--quick`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Budget {
    /// The case name.
    pub case: &'static str,
    /// Wall seconds of the default run.
    pub default_s: f64,
    /// Wall seconds of the `--quick` run.
    pub quick_s: f64,
}

const fn b(case: &'static str, default_s: f64, quick_s: f64) -> Budget {
    Budget {
        case,
        default_s,
        quick_s,
    }
}

/// Every validation case's budget, in the order of the run.
pub const BUDGETS: &[Budget] = &[
    b("rigid-incline", 1.0, 1.0),
    b("rigid-pendulum", 4.0, 3.0),
    b("rigid-stack", 3.0, 2.0),
    b("rigid-stack-heavy", 3.0, 2.0),
    b("rigid-free-fall", 1.0, 1.0),
    b("rigid-spin", 1.0, 1.0),
    b("smc-bounce", 1.0, 1.0),
    b("granular-settle", 7.0, 7.0),
    b("granular-hopper", 43.0, 43.0),
    b("granular-ball-drop", 110.0, 76.0),
    b("granular-shear", 90.0, 40.0),
    b("granular-repose", 16.0, 16.0),
    b("sph-hydrostatic", 29.0, 12.0),
    b("sph-poiseuille", 10.0, 3.0),
    b("sph-dam-break", 51.0, 30.0),
    b("sph-sloshing", 41.0, 41.0),
    b("fsi-floating-body", 40.0, 12.0),
    b("fsi-flexible-beam", 15.0, 8.0),
    b("fsi-cylinder-array", 15.0, 8.0),
    b("fsi-sphere-settling", 4.0, 2.0),
    b("fsi-sphere-heave", 6.0, 6.0),
    b("fsi-active-domain", 16.0, 10.0),
    b("fsi-channel", 15.0, 10.0),
    b("fsi-jeffery", 12.0, 8.0),
    b("fsi-cylinder-flow", 6.0, 6.0),
    b("cfluid-incompressibility", 34.0, 16.0),
    b("cfluid-dam-break", 25.0, 14.0),
    b("cfluid-floating-box", 51.0, 51.0),
    b("cfluid-timestep", 18.0, 18.0),
    b("cfluid-sloshing", 8.0, 8.0),
    b("cfluid-sloshing-decay", 17.0, 17.0),
    b("cfluid-still-water", 12.0, 12.0),
    b("ccp-solvers", 35.0, 4.0),
    b("fea-cantilever", 1.0, 1.0),
    b("fea-cantilever-frequency", 1.0, 1.0),
    b("fea-pendulum", 13.0, 4.0),
    b("fea-tet-patch", 1.0, 1.0),
    b("fea-tet-cantilever", 20.0, 7.0),
    b("fea-shell-cantilever", 1.0, 1.0),
    b("fea-shell-pressure", 1.0, 1.0),
    b("fea-bend-45", 1.0, 1.0),
    b("fea-tire-drop", 4.0, 4.0),
    b("fea-tire-static", 5.0, 2.0),
    b("fea-tire-rolling", 12.0, 4.0),
    b("mpm-elastic-bar", 9.0, 1.0),
    b("mpm-snow", 6.0, 4.0),
    b("mpm-footing", 15.0, 8.0),
    b("mpm-column-collapse", 15.0, 10.0),
    b("mpm-wheel", 17.0, 15.0),
    b("hmmwv-static", 2.0, 2.0),
    b("hmmwv-accel", 15.0, 3.0),
    b("hmmwv-turn", 11.0, 5.0),
    b("hmmwv-lane-change", 4.0, 4.0),
    b("hmmwv-granular", 96.0, 94.0),
    b("m113-static", 11.0, 11.0),
    b("m113-accel", 25.0, 17.0),
    b("m113-turn", 18.0, 18.0),
    b("m113-step", 10.0, 10.0),
    b("m113-granular", 25.0, 15.0),
];

/// The budget of `case` in `mode` (s); `None` for an unknown case or `--full` (which
/// has no limit).
pub fn budget_s(case: &str, mode: Mode) -> Option<f64> {
    let b = BUDGETS.iter().find(|b| b.case == case)?;
    match mode {
        Mode::Default => Some(b.default_s),
        Mode::Quick => Some(b.quick_s),
        Mode::Full => None,
    }
}

/// The budgets summed by area (the prefix of the case name up to its first `-`,
/// `smc-bounce` counted as granular, `hmmwv-*` as vehicle), in seconds at the defaults.
pub fn area_shares() -> Vec<(&'static str, f64)> {
    let mut shares: Vec<(&'static str, f64)> = Vec::new();
    for b in BUDGETS {
        let area = match b.case.split('-').next().unwrap_or(b.case) {
            "smc" => "granular",
            "hmmwv" | "m113" => "vehicle",
            a => a,
        };
        match shares.iter_mut().find(|(a, _)| *a == area) {
            Some((_, s)) => *s += b.default_s,
            None => shares.push((area, b.default_s)),
        }
    }
    shares
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cases::all_cases;

    #[test]
    fn every_case_has_a_budget_and_the_plan_fits_the_limit() {
        let cases = all_cases();
        for c in &cases {
            assert!(
                budget_s(c.name(), Mode::Default).is_some(),
                "no budget for {}",
                c.name()
            );
        }
        assert_eq!(
            cases.len(),
            BUDGETS.len(),
            "a budget for a case that is not registered"
        );
        let total: f64 = BUDGETS.iter().map(|b| b.default_s).sum();
        assert!(
            total <= PLANNED_FRACTION * DEFAULT_RUN_S,
            "budgets sum to {total} s, over {PLANNED_FRACTION} x {DEFAULT_RUN_S} s"
        );
        let areas: f64 = area_shares().iter().map(|(_, s)| s).sum();
        assert!((areas - total).abs() < 1e-9);
        assert!(BUDGETS.iter().all(|b| b.quick_s <= b.default_s));
        assert_eq!(budget_s("rigid-incline", Mode::Full), None);
    }
}
