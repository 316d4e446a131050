//! The registry of validation cases and benches.
//!
//! # How to add a case
//!
//! 1. Write the case in `xtask/src/cases/<area>/<case>.rs` (one file per case), using
//!    only the public API of the chrono crates. Declare the area module here
//!    (`pub mod rigid;`) and the file in the area's `mod.rs` (`pub mod incline;`).
//! 2. Add it, one line, to the list in [`all_cases`] (validation, with checks) or
//!    [`all_benches`] (throughput, metrics only): `rigid::incline::case(),`.
//! 3. Run `cargo xtask list`, then `cargo xtask validate <name> --quick`.
//!
//! A case is a parameter struct (`Default` = the published or analytic setup), a
//! `const` table documenting each field, and a run function:
//!
//! ```
//! use serde::{Deserialize, Serialize};
//! use xtask::case::{Case, CaseOutput, Check, Mode, PlotSpec, RunContext, Series};
//! use xtask::params::{CaseParams, ParamCase, ParamInfo};
//!
//! #[derive(Clone, Serialize, Deserialize)]
//! pub struct FallParams { pub h: f64, pub t_end: f64 }
//! impl Default for FallParams {
//!     fn default() -> Self { Self { h: 1e-3, t_end: 1.0 } }
//! }
//! impl CaseParams for FallParams {
//!     const INFO: &'static [ParamInfo] = &[
//!         ParamInfo::new("h", "s", "time step"),
//!         ParamInfo::new("t_end", "s", "simulated time"),
//!     ];
//!     fn apply_mode(&mut self, mode: Mode) { if mode == Mode::Quick { self.t_end = 0.1 } }
//! }
//! fn run(p: &FallParams, ctx: &RunContext) -> anyhow::Result<CaseOutput> {
//!     anyhow::ensure!(p.h > 0.0, "h must be positive, got {}", p.h);
//!     let n = (p.t_end / p.h).round() as u64;
//!     let (mut z, mut v) = (0.0, 0.0);
//!     let mut series = Series::new(["t", "z", "z_exact"]);
//!     for i in 1..=n {
//!         v -= 9.81 * p.h; // semi-implicit Euler
//!         z += v * p.h;
//!         let t = i as f64 * p.h;
//!         series.push(&[t, z, -0.5 * 9.81 * t * t]);
//!         ctx.progress_steps(i, n);
//!     }
//!     let mut out = CaseOutput::new();
//!     out.check(Check::relative("z_end", z, -0.5 * 9.81 * p.t_end.powi(2), 1e-2));
//!     out.series = series;
//!     out.plot = PlotSpec::new("free fall", "t [s]", "z [m]", &["z"]).with_reference(&["z_exact"]);
//!     out.steps = n;
//!     Ok(out)
//! }
//! pub fn case() -> Box<dyn Case> {
//!     ParamCase::<FallParams>::boxed("rigid-fall", "rigid", "Free fall against z = -g t^2 / 2.", run)
//! }
//! # let out = case().run(&RunContext::new(Mode::Quick, std::env::temp_dir(), false)).unwrap();
//! # assert!(out.all_pass());
//! ```

use crate::case::Case;

pub mod ccp;
pub mod cfluid;
pub mod fea;
pub mod fsi;
pub mod granular;
pub mod mpm;
pub mod rigid;
pub mod sph;
mod timed_solver;
pub mod vehicle;

/// All validation cases, in the order `cargo xtask validate` runs them.
pub fn all_cases() -> Vec<Box<dyn Case>> {
    vec![
        rigid::incline::case(),
        rigid::pendulum::case(),
        rigid::stack::case(),
        rigid::stack::heavy_case(),
        rigid::free_fall::case(),
        rigid::spin::case(),
        granular::smc_bounce::case(),
        granular::settle::case(),
        granular::hopper::case(),
        granular::ball_drop::case(),
        granular::shear::case(),
        granular::repose::case(),
        sph::hydrostatic::case(),
        sph::poiseuille::case(),
        sph::dam_break::case(),
        sph::sloshing::case(),
        fsi::floating_body::case(),
        fsi::active_domain::case(),
        fsi::flexible_beam::case(),
        fsi::cylinder_array::case(),
        fsi::sphere_settling::case(),
        fsi::sphere_heave::case(),
        fsi::channel::case(),
        fsi::jeffery::case(),
        fsi::cylinder_flow::case(),
        cfluid::incompressibility::case(),
        cfluid::dam_break::case(),
        cfluid::floating_box::case(),
        cfluid::timestep::case(),
        cfluid::sloshing::case(),
        cfluid::sloshing_decay::case(),
        cfluid::still_water::case(),
        ccp::solvers::case(),
        fea::cantilever::case(),
        fea::frequency::case(),
        fea::pendulum::case(),
        fea::tet_patch::case(),
        fea::tet_cantilever::case(),
        fea::shell_cantilever::case(),
        fea::shell_pressure::case(),
        fea::bend45::case(),
        fea::tire_drop::case(),
        fea::tire_static::case(),
        fea::tire_rolling::case(),
        mpm::elastic_bar::case(),
        mpm::snow::case(),
        mpm::footing::case(),
        mpm::column_collapse::case(),
        mpm::wheel::case(),
        vehicle::static_settle::case(),
        vehicle::accel::case(),
        vehicle::turn::case(),
        vehicle::lane_change::case(),
        vehicle::granular::case(),
        vehicle::m113_static::case(),
        vehicle::m113_accel::case(),
        vehicle::m113_turn::case(),
        vehicle::m113_step::case(),
        vehicle::m113_granular::case(),
    ]
}

/// All benches (whole-scene throughput runs: metrics such as steps/s, no checks), in the
/// order `cargo xtask bench` runs them.
pub fn all_benches() -> Vec<Box<dyn Case>> {
    vec![
        // Register benches here, one line each, e.g.
        // granular::bench_spheres::case(),
        granular::settle::bench(),
        ccp::apply_n::case(),
        sph::bench::bench(),
        mpm::settle::bench(),
        // Only with `--features rapier` (`cargo xtask-rapier`): the default build does not
        // compile rapier.
        #[cfg(feature = "rapier")]
        granular::vs_rapier::bench(),
    ]
}

/// Problems with how a set of cases is declared (duplicate names, parameters without a
/// [`ParamInfo`](crate::params::ParamInfo) entry or the reverse). Empty when all is well.
pub fn registry_problems(cases: &[Box<dyn Case>]) -> Vec<String> {
    let mut problems = Vec::new();
    let mut names = std::collections::BTreeSet::new();
    for case in cases {
        let name = case.name();
        if name.is_empty() || case.area().is_empty() || case.description().is_empty() {
            problems.push(format!("`{name}`: empty name, area or description"));
        }
        if !names.insert(name) {
            problems.push(format!("`{name}`: registered twice"));
        }
        let params = case.params_json();
        let Some(map) = params.as_object() else {
            problems.push(format!("`{name}`: parameters are not a JSON object"));
            continue;
        };
        let info = case.param_info();
        for key in map.keys() {
            if !info.iter().any(|i| i.name == key) {
                problems.push(format!(
                    "`{name}`: parameter `{key}` has no ParamInfo entry"
                ));
            }
        }
        for i in &info {
            if !map.contains_key(i.name) {
                problems.push(format!(
                    "`{name}`: ParamInfo `{}` is not a parameter",
                    i.name
                ));
            }
        }
    }
    problems
}

#[cfg(test)]
pub(crate) mod testing {
    //! Test-only cases: an exponential decay with analytic reference, and a case that
    //! fails (error or panic).

    use serde::{Deserialize, Serialize};

    use crate::case::{Case, CaseOutput, Check, Mode, PlotSpec, RunContext, Series, SweepPoint};
    use crate::params::{CaseParams, ParamCase, ParamInfo};

    #[derive(Clone, Serialize, Deserialize)]
    pub struct DecayParams {
        pub k: f64,
        pub h: f64,
        pub t_end: f64,
        pub steps_hint: u64,
        pub label: String,
        pub flag: bool,
    }

    impl Default for DecayParams {
        fn default() -> Self {
            Self {
                k: 1.0,
                h: 0.01,
                t_end: 1.0,
                steps_hint: 0,
                label: "decay".into(),
                flag: false,
            }
        }
    }

    impl CaseParams for DecayParams {
        const INFO: &'static [ParamInfo] = &[
            ParamInfo::new("k", "1/s", "decay rate"),
            ParamInfo::new("h", "s", "time step"),
            ParamInfo::new("t_end", "s", "simulated time"),
            ParamInfo::new("steps_hint", "-", "unused integer"),
            ParamInfo::new("label", "-", "unused string"),
            ParamInfo::new("flag", "-", "unused boolean"),
        ];
        fn apply_mode(&mut self, mode: Mode) {
            if mode == Mode::Quick {
                self.t_end = 0.5;
            }
        }
    }

    /// Explicit Euler for x' = -k x, x(0) = 1.
    fn euler(k: f64, h: f64, t_end: f64) -> (f64, u64, Series) {
        let n = (t_end / h).round() as u64;
        let mut x = 1.0;
        let mut s = Series::new(["t", "x", "x_exact"]);
        s.push(&[0.0, 1.0, 1.0]);
        for i in 1..=n {
            x -= h * k * x;
            let t = i as f64 * h;
            s.push(&[t, x, (-k * t).exp()]);
        }
        (x, n, s)
    }

    fn run_decay(p: &DecayParams, ctx: &RunContext) -> anyhow::Result<CaseOutput> {
        anyhow::ensure!(p.h > 0.0, "h must be positive, got {}", p.h);
        let (x, n, series) = euler(p.k, p.h, p.t_end);
        ctx.progress(1.0);
        let exact = (-p.k * p.t_end).exp();
        let mut out = CaseOutput::new();
        out.check(Check::relative("x_end", x, exact, 0.02))
            .check(Check::absolute("x_end_abs", x, exact, 0.01))
            .check(Check::below("x_min", x, 1.0))
            .metric("not_finite", f64::NAN);
        let mut reference = Series::new(["t", "x_ref"]);
        for i in 0..=10 {
            let t = p.t_end * i as f64 / 10.0;
            reference.push(&[t, (-p.k * t).exp()]);
        }
        out.reference_series = Some(reference);
        out.series = series;
        out.plot = PlotSpec::new("decay", "t [s]", "x [-]", &["x"]).with_reference(&["x_ref"]);
        out.steps = n;
        for (i, h) in [p.h, p.h / 2.0, p.h / 4.0].into_iter().enumerate() {
            let start = std::time::Instant::now();
            let (xh, _, _) = euler(p.k, h, p.t_end);
            out.sweep.push(SweepPoint {
                label: format!("h/{}", 1 << i),
                error: (xh - exact).abs(),
                wall_s: start.elapsed().as_secs_f64().max(1e-9),
            });
        }
        Ok(out)
    }

    /// The decay case (`test-decay`, area `test`).
    pub fn decay_case() -> Box<dyn Case> {
        ParamCase::<DecayParams>::boxed(
            "test-decay",
            "test",
            "x' = -k x by explicit Euler.",
            run_decay,
        )
    }

    #[derive(Clone, Default, Serialize, Deserialize)]
    pub struct FailParams {
        pub h: f64,
        pub panic: bool,
    }

    impl CaseParams for FailParams {
        const INFO: &'static [ParamInfo] = &[
            ParamInfo::new("h", "s", "time step"),
            ParamInfo::new("panic", "-", "panic instead of returning an error"),
        ];
    }

    fn run_fail(p: &FailParams, _ctx: &RunContext) -> anyhow::Result<CaseOutput> {
        assert!(!p.panic, "deliberate panic");
        anyhow::bail!("diverged at step 3")
    }

    /// A case that always fails (`test-fail`, area `test`).
    pub fn failing_case() -> Box<dyn Case> {
        ParamCase::<FailParams>::boxed("test-fail", "test", "Always fails.", run_fail)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn registered_cases_are_well_formed() {
        assert_eq!(registry_problems(&all_cases()), Vec::<String>::new());
        assert_eq!(registry_problems(&all_benches()), Vec::<String>::new());
        let test_cases = vec![testing::decay_case(), testing::failing_case()];
        assert_eq!(registry_problems(&test_cases), Vec::<String>::new());
        let twice = vec![testing::decay_case(), testing::decay_case()];
        assert_eq!(registry_problems(&twice).len(), 1);
    }
}
