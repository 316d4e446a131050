//! `granular-hopper`: discharge of a flat-bottomed cylindrical silo through a circular
//! orifice, against Beverloo's law.
//!
//! Reference: W. A. Beverloo, H. A. Leniger and J. van de Velde, "The flow of granular
//! solids through orifices", Chem. Eng. Sci. 15 (1961) 260–269:
//! `W = C rho_b sqrt(g) (D - k d)^(5/2)` (kg/s), with `rho_b` the bulk density of the
//! material in the silo, `D` the orifice diameter, `d` the grain diameter, and the customary
//! constants for spheres `C = 0.58`, `k = 1.5` (R. M. Nedderman, *Statics and Kinematics of
//! Granular Materials*, Cambridge 1992, ch. 10: `C` in 0.55–0.65, `k` in 1.3–2.9, 1.5 the
//! usual value for spheres). `rho_b` is measured in the run, in a band of the silo away
//! from the orifice, the walls and the free surface.
//!
//! Scene, for each orifice diameter `D` of the sweep: a silo of diameter
//! `max(silo_ratio D, D + 10 d)` (walls: a 32-sided polygon of half-spaces), a floor that is
//! a triangle-mesh annulus (48 sides, the hole's area equal to the circle's), grains of
//! diameters uniform in `[0.9 d, d]` filled from a jittered lattice to `fill_height` after
//! settling (Beverloo's `d` is their mean diameter, `0.95 d`). The discharge starts at once; a grain that has fallen `5 d` below the floor
//! counts as discharged, is removed, and a grain like it is added on top of the pile at rest
//! (`chrono_core::granular::Recycler`; recycling keeps the
//! head constant, so the flow is steady after the initial collapse). The flow rate is the
//! least-squares slope of the discharged mass against time after `t_transient`.
//! `seed` lists the packings: each orifice discharges once per seed and the check takes
//! the mean rate against Beverloo's at the mean bulk density (per-seed values carry a
//! `_seed{N}` suffix, the spread is `flow_rate_std_*`). The default and `--quick` run one
//! seed, `--full` three.
//!
//! Both methods: `method = nsc` (DEM-C: friction cones, APGD) or `smc` (DEM-P: Hertz–Mindlin).

use chrono_core::granular::probe::{bulk_density, line_fit};
use chrono_core::granular::{GrainBed, Recycler, Region, Silo};
use chrono_core::math::Vector3;
use chrono_core::system::{ContactMethod, SmcSettings};
use chrono_core::{ContactMaterial, SystemSettings};
use serde::{Deserialize, Serialize};

use super::{make_system, method_name};
use crate::case::{Case, CaseOutput, Check, Mode, PlotSpec, RunContext, Series, SweepPoint};
use crate::fit::mean_std;
use crate::params::{CaseParams, ParamCase, ParamInfo, ensure_positive};

/// Beverloo's constant `C` for spheres.
pub const BEVERLOO_C: f64 = 0.58;
/// Beverloo's empty-annulus constant `k` for spheres.
pub const BEVERLOO_K: f64 = 1.5;

/// Beverloo's mass flow rate (kg/s) through a circular orifice of diameter `orifice` (m)
/// for grains of diameter `grain` (m) at bulk density `rho_b` (kg/m^3) and gravity `g`.
pub fn beverloo(rho_b: f64, g: f64, orifice: f64, grain: f64) -> f64 {
    BEVERLOO_C * rho_b * g.sqrt() * (orifice - BEVERLOO_K * grain).max(0.0).powf(2.5)
}

/// Parameters of `granular-hopper` (`Default` is the `--full` setup: D/d = 5, 7.5, 10).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct HopperParams {
    /// Orifice diameters of the sweep, m (a single number runs one).
    pub orifice_diameter: Vec<f64>,
    /// Largest grain diameter `d`, m (diameters uniform in [0.9 d, d]).
    pub grain_diameter: f64,
    /// Sliding friction coefficient (grain–grain and grain–wall). Default 0.3, a usual
    /// DEM value for glass beads; the flow rate falls with friction (at 0.5 it is ~17 %
    /// below Beverloo's `C = 0.58`; Darias, Madrid and Pugnaloni, Phys. Rev. E 101, 052905,
    /// 2020, show the friction dependence by DEM).
    pub mu: f64,
    /// Rolling friction coefficient (dimensionless, NSC cones `mu_r R`; SMC torque).
    pub rolling_friction: f64,
    /// Height of the settled fill, m (0: `fill_orifices` orifice diameters, or the silo
    /// diameter if that is 0 too).
    pub fill_height: f64,
    /// Height of the settled fill in orifice diameters when `fill_height` is 0 (0: the silo
    /// diameter; `--quick` and the default run: 2).
    pub fill_orifices: f64,
    /// Silo diameter over orifice diameter (at least `D + 10 d`).
    pub silo_ratio: f64,
    /// Contact method: `nsc` or `smc`.
    pub method: ContactMethod,
    /// Grain density, kg/m^3.
    pub density: f64,
    /// Young's modulus (SMC), Pa.
    pub young: f64,
    /// Restitution (SMC).
    pub restitution: f64,
    /// Time step, s (0: 1e-3 for NSC, the SMC limit for SMC).
    pub h: f64,
    /// Start of the steady window, s.
    pub t_transient: f64,
    /// Simulated time per orifice, s.
    pub t_end: f64,
    /// APGD tolerance (NSC), m/s.
    pub tolerance: f64,
    /// APGD iteration cap (NSC).
    pub max_iterations: usize,
    /// Relative tolerance of the flow rate against Beverloo.
    pub rel_tolerance: f64,
    /// Seeds of the packing and of the re-insertion positions: one discharge per orifice
    /// and seed; the flow rate is checked on the mean over the seeds (a single discharge
    /// scatters: seeds 3 / 4 / 5 gave -10.0 / -3.4 / +3.9 % at D = 5 d).
    pub seed: Vec<u64>,
}

impl Default for HopperParams {
    fn default() -> Self {
        let d = 0.004;
        Self {
            orifice_diameter: vec![5.0 * d, 7.5 * d, 10.0 * d],
            grain_diameter: d,
            mu: 0.3,
            rolling_friction: 0.0,
            fill_height: 0.0,
            fill_orifices: 0.0,
            silo_ratio: 2.5,
            method: ContactMethod::Nsc,
            density: 2500.0,
            young: 1e7,
            restitution: 0.5,
            h: 0.0,
            t_transient: 0.4,
            t_end: 1.2,
            tolerance: 1e-4,
            max_iterations: 60,
            rel_tolerance: 0.15,
            seed: vec![3, 4, 5],
        }
    }
}

impl CaseParams for HopperParams {
    const INFO: &'static [ParamInfo] = &[
        ParamInfo::new(
            "orifice_diameter",
            "m",
            "orifice diameters of the sweep ([a, b, ..] or one number)",
        ),
        ParamInfo::new(
            "grain_diameter",
            "m",
            "largest grain diameter d (diameters in [0.9 d, d])",
        ),
        ParamInfo::new("mu", "-", "sliding friction coefficient"),
        ParamInfo::new("rolling_friction", "-", "rolling friction coefficient"),
        ParamInfo::new(
            "fill_height",
            "m",
            "settled fill height (0: fill_orifices x the orifice, or the silo diameter)",
        ),
        ParamInfo::new(
            "fill_orifices",
            "-",
            "fill height in orifice diameters when fill_height = 0 (0: the silo diameter)",
        ),
        ParamInfo::new(
            "silo_ratio",
            "-",
            "silo diameter / orifice diameter (at least D + 10 d)",
        ),
        ParamInfo::new("method", "-", "contact method: nsc | smc"),
        ParamInfo::new("density", "kg/m^3", "grain density"),
        ParamInfo::new("young", "Pa", "Young's modulus (SMC)"),
        ParamInfo::new("restitution", "-", "restitution (SMC)"),
        ParamInfo::new("h", "s", "time step (0: 1e-3 NSC, the SMC limit SMC)"),
        ParamInfo::new("t_transient", "s", "start of the steady window"),
        ParamInfo::new("t_end", "s", "simulated time per orifice"),
        ParamInfo::new("tolerance", "m/s", "APGD tolerance (NSC)"),
        ParamInfo::new("max_iterations", "-", "APGD iteration cap (NSC)"),
        ParamInfo::new("rel_tolerance", "-", "relative tolerance of the flow rate"),
        ParamInfo::new(
            "seed",
            "-",
            "seeds of the packing and re-insertion: one discharge per orifice and seed, the check takes the mean",
        ),
    ];
    fn apply_mode(&mut self, mode: Mode) {
        match mode {
            // A fill of 10 d (2 orifice diameters, 2/3 of the silo's) instead of the silo
            // diameter: 2/3 of the grains for a flow rate 2 % lower (-8.5 % against Beverloo
            // instead of -6.8 %, docs/validation-granular.md), the smallest silo (D = 5 d),
            // the rate fitted over 0.3-1.0 s (~110 s), for the 20-minute budget of the
            // default run (`xtask/src/budget.rs`), which runs the same discharge as
            // `--quick`. The window was 0.3-0.7 s until the silo re-inserted grains instead
            // of moving them: with the new grain order, seeds 3 / 4 / 5 gave -15.0 / -8.0 /
            // -0.2 % over it and -10.0 / -3.4 / +3.9 % over 0.3-1.0 s (the short window
            // weighs the start of the flow, which runs low). `--full`
            // runs D = 5, 7.5 and 10 d (3k, 6k, 15k grains) with the full fill, each with
            // seeds 3, 4 and 5; the earlier
            // default, D = 5 and 7.5 d with the full fill, is
            // `--set 'orifice_diameter=[0.02,0.03]' --set fill_orifices=0 --set t_transient=0.4
            // --set t_end=1.2`. The fill is given in orifice diameters (2: 10 d at D = 5 d,
            // the same bits) so that another orifice keeps its measuring band.
            Mode::Quick | Mode::Default => {
                self.orifice_diameter = vec![5.0 * self.grain_diameter];
                self.seed = vec![3];
                self.fill_orifices = 2.0;
                self.t_transient = 0.3;
                self.t_end = 1.0;
            }
            Mode::Full => {}
        }
    }
}

/// One discharge run: the measured flow rate and bulk density, and the series of the
/// discharged mass.
struct Discharge {
    flow_rate: f64,
    bulk_density: f64,
    grains: usize,
    steps: u64,
    wall_s: f64,
    series: Vec<(f64, f64)>,
}

fn discharge(
    p: &HopperParams,
    orifice: f64,
    seed: u64,
    ctx: &RunContext,
    progress: (usize, usize),
) -> anyhow::Result<Discharge> {
    let start = std::time::Instant::now();
    let d = p.grain_diameter;
    ensure_positive("grain_diameter", d)?;
    anyhow::ensure!(
        orifice > 2.0 * d && orifice.is_finite(),
        "parameter `orifice_diameter` must exceed 2 grain diameters, got {orifice}"
    );
    let method = p.method;
    let silo = (p.silo_ratio * orifice).max(orifice + 10.0 * d);
    anyhow::ensure!(
        p.fill_orifices.is_finite() && p.fill_orifices >= 0.0,
        "parameter `fill_orifices` must be finite and >= 0, got {}",
        p.fill_orifices
    );
    let fill = if p.fill_height > 0.0 {
        p.fill_height
    } else if p.fill_orifices > 0.0 {
        p.fill_orifices * orifice
    } else {
        silo
    };
    // The measuring band of the bulk density: above the orifice's influence, below the
    // surface (at 0.8 of the fill height), away from the wall; it must hold 2 grains.
    let (band_lo, band_r) = (orifice.max(4.0 * d), 0.5 * silo - 2.0 * d);
    anyhow::ensure!(
        0.8 * fill > band_lo + 2.0 * d,
        "parameter `fill_height` / `fill_orifices`: the fill {fill} m is too low to measure \
         the bulk density between {band_lo} m (the orifice's reach) and 0.8 of the fill: \
         it must exceed {} m",
        (band_lo + 2.0 * d) / 0.8
    );
    let settings = SystemSettings {
        envelope: 0.05 * d,
        smc: SmcSettings::default(),
        ..SystemSettings::default()
    };
    let mut sys = make_system(method, settings, p.tolerance, p.max_iterations)?;
    let mat = ContactMaterial::smc(p.young, 0.3, p.restitution, p.mu)
        .with_rolling_friction(p.rolling_friction);
    mat.validate()?;
    let vessel = Silo::new(silo, orifice, 2.0 * d, mat);
    vessel.add(&mut sys)?;
    // A loose lattice settles to ~0.6: fill 2.6x higher. No settling before the
    // discharge: the grains fall onto the floor and start flowing at once.
    let r = 0.5 * d;
    let bed = GrainBed {
        seed,
        ..GrainBed::new(
            vessel.region(0.5 * r, 2.6 * fill),
            0.9 * r,
            r,
            p.density,
            mat,
        )
    }
    .pour(&mut sys)?;
    let h = super::step_size(p.h, method, &sys);
    let n = (p.t_end / h).round().max(1.0) as u64;
    let mut series = Vec::new();
    let (mut rho_sum, mut rho_n) = (0.0, 0usize);
    let mut recycler = Recycler::new(&sys, &bed, &vessel, d, fill + 2.0 * d)?;
    let record_every = ((0.01 / h).round() as u64).max(1);
    for i in 1..=n {
        sys.step(h)?;
        recycler.recycle(&mut sys)?;
        let t = sys.time();
        if i % record_every == 0 || i == n {
            series.push((t, recycler.discharged()));
            if t >= p.t_transient {
                let band_hi = 0.8 * fill;
                if band_hi > band_lo + 2.0 * d {
                    let band = Region::Cylinder {
                        base: Vector3::new(0.0, 0.0, band_lo),
                        radius: band_r,
                        height: band_hi - band_lo,
                    };
                    let grains = (recycler.handles().iter())
                        .zip(recycler.masses())
                        .map(|(&b, &m)| Ok((sys.body(b)?.position(), m)))
                        .collect::<anyhow::Result<Vec<_>>>()?;
                    rho_sum += bulk_density(grains, &band);
                    rho_n += 1;
                }
            }
        }
        let (j, m) = progress;
        ctx.progress((j as f64 + i as f64 / n as f64) / m as f64);
    }
    let steady: Vec<(f64, f64)> = series
        .iter()
        .copied()
        .filter(|(t, _)| *t >= p.t_transient)
        .collect();
    anyhow::ensure!(
        steady.len() >= 5 && rho_n > 0,
        "granular-hopper: the steady window (t >= t_transient = {}) is too short for t_end = {}",
        p.t_transient,
        p.t_end
    );
    Ok(Discharge {
        flow_rate: line_fit(&steady).map_or(f64::NAN, |(a, _)| a),
        bulk_density: rho_sum / rho_n as f64,
        grains: bed.len(),
        steps: n,
        wall_s: start.elapsed().as_secs_f64(),
        series,
    })
}

fn run(p: &HopperParams, ctx: &RunContext) -> anyhow::Result<CaseOutput> {
    anyhow::ensure!(
        !p.orifice_diameter.is_empty(),
        "parameter `orifice_diameter` must list at least one diameter"
    );
    anyhow::ensure!(
        !p.seed.is_empty(),
        "parameter `seed` must list at least one seed"
    );
    let mut out = CaseOutput::new();
    let g = chrono_core::math::GRAVITY.norm();
    let mut columns = vec!["t".to_string()];
    let nseed = p.seed.len();
    let total = p.orifice_diameter.len() * nseed;
    let mut runs = Vec::new();
    let mut rates = Vec::new();
    for (j, &orifice) in p.orifice_diameter.iter().enumerate() {
        let ratio = orifice / p.grain_diameter;
        let tag = format!("D{:.1}d", ratio);
        let (mut flow, mut rho, mut wall_s) = (Vec::new(), Vec::new(), 0.0);
        for (k, &seed) in p.seed.iter().enumerate() {
            let r = discharge(p, orifice, seed, ctx, (j * nseed + k, total))?;
            // One seed: the run's names are the case's (as before ensembles).
            let run_tag = if nseed > 1 {
                format!("{tag}_seed{seed}")
            } else {
                tag.clone()
            };
            if nseed > 1 {
                out.metric(format!("flow_rate_{run_tag}"), r.flow_rate);
            }
            out.metric(format!("bulk_density_{run_tag}"), r.bulk_density)
                .metric(format!("grains_{run_tag}"), r.grains as f64)
                .metric(format!("wall_s_{run_tag}"), r.wall_s);
            flow.push(r.flow_rate);
            rho.push(r.bulk_density);
            wall_s += r.wall_s;
            out.steps += r.steps;
            columns.push(format!("discharged_kg_{run_tag}"));
            runs.push(r);
        }
        // The mean rate against Beverloo's at the mean bulk density. Beverloo's d: the
        // mean diameter of the grains (uniform in [0.9 d, d]).
        let ((rate, spread), (rho_b, _)) = (mean_std(&flow), mean_std(&rho));
        let reference = beverloo(rho_b, g, orifice, 0.95 * p.grain_diameter);
        out.check(Check::relative(
            format!("flow_rate_{tag}"),
            rate,
            reference,
            p.rel_tolerance,
        ));
        out.metric(format!("beverloo_{tag}"), reference);
        if nseed > 1 {
            out.metric(format!("flow_rate_std_{tag}"), spread)
                .metric(format!("bulk_density_{tag}"), rho_b);
        }
        out.sweep.push(SweepPoint {
            label: format!("{}_{tag}", method_name(p.method)),
            error: ((rate - reference) / reference).abs(),
            wall_s,
        });
        rates.push(rate);
    }
    if let [only] = rates.as_slice() {
        out.metric("flow_rate", *only);
    }
    // Series: the discharged mass of every orifice on a common time axis.
    let cols: Vec<&str> = columns.iter().map(String::as_str).collect();
    let mut series = Series::new(cols.iter().copied());
    let len = runs.iter().map(|r| r.series.len()).min().unwrap_or(0);
    for k in 0..len {
        let mut row = vec![runs[0].series[k].0];
        row.extend(runs.iter().map(|r| r.series[k].1));
        series.push(&row);
    }
    out.series = series;
    out.plot = PlotSpec::new(
        "silo discharge (mass through the orifice)",
        "t [s]",
        "discharged mass [kg]",
        &cols[1..],
    );
    Ok(out)
}

/// The validation case.
pub fn case() -> Box<dyn Case> {
    ParamCase::<HopperParams>::boxed(
        "granular-hopper",
        "granular",
        "Flat-bottomed silo discharging through a circular orifice (NSC or SMC): flow rate against Beverloo's law W = C rho_b sqrt(g) (D - k d)^(5/2), C = 0.58, k = 1.5.",
        run,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn beverloo_formula() {
        // 0.58 * 1500 * sqrt(g) * (0.05 - 0.0075)^2.5
        let g = chrono_core::math::GRAVITY.norm();
        let w = beverloo(1500.0, g, 0.05, 0.005);
        let expect = 0.58 * 1500.0 * g.sqrt() * 0.0425f64.powf(2.5);
        assert!((w - expect).abs() < 1e-12);
        assert_eq!(beverloo(1500.0, g, 0.005, 0.005), 0.0);
    }

    #[test]
    fn empty_lists_are_errors_naming_the_field() {
        let ctx = RunContext::new(Mode::Quick, "/nonexistent", false);
        let mut p = HopperParams {
            seed: vec![],
            ..HopperParams::default()
        };
        let e = run(&p, &ctx).unwrap_err().to_string();
        assert!(e.contains("`seed`"), "{e}");
        p.seed = vec![3];
        p.orifice_diameter = vec![];
        let e = run(&p, &ctx).unwrap_err().to_string();
        assert!(e.contains("`orifice_diameter`"), "{e}");
    }

    #[test]
    fn quick_and_default_run_one_seed_full_three() {
        for (mode, n) in [(Mode::Quick, 1), (Mode::Default, 1), (Mode::Full, 3)] {
            let mut p = HopperParams::default();
            p.apply_mode(mode);
            assert_eq!(p.seed.len(), n, "{mode:?}");
        }
    }
}
