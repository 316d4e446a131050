//! `sph-poiseuille`: start-up of plane Poiseuille flow driven by a body force
//! (Morris, Fox and Zhu, J. Comput. Phys. 136 (1997) 214-226).
//!
//! Channel of width `L` between walls at `z = 0` and `z = L` (marker layers, no-slip by
//! extrapolation), periodic along x and y, fluid at rest at `t = 0`, body force `F`
//! along x. Reference: the transient series solution
//! ([`chrono_sph::analytic::poiseuille_startup`]); its tabulated form is
//! `data/reference/poiseuille_startup_series.csv`. Metric `profile_error`: the
//! largest relative L2 error of the layer-averaged velocity profile over the times
//! `tau = nu t / L^2 = 0.0225, 0.045, 0.1125` and the steady state (`tau = 1`).

use std::time::Instant;

use chrono_sph::analytic::poiseuille_startup;
use chrono_sph::{SphBuilder, SphSettings, sound_speed_for};
use serde::{Deserialize, Serialize};

use super::{convergence_order, rel_l2, sweep_point, sweep_spacings};
use crate::case::{Case, CaseOutput, Check, Mode, PlotSpec, RunContext, Series};
use crate::params::{CaseParams, ParamCase, ParamInfo};
use chrono_core::particles::lattice::{slab_layers, wall_layers};

/// Parameters of `sph-poiseuille` (defaults: Morris et al. 1997).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct PoiseuilleParams {
    /// Particle spacing, m.
    pub spacing: f64,
    /// Kinematic viscosity `nu`, m^2/s.
    pub viscosity: f64,
    /// Body force per unit mass `F`, m/s^2.
    pub body_force: f64,
    /// Channel width `L`, m.
    pub channel_width: f64,
    /// Extra coarser runs for the sweep (spacing x 1.5^k).
    pub sweep: u32,
}

impl Default for PoiseuilleParams {
    fn default() -> Self {
        Self {
            spacing: 1e-3 / 30.0,
            viscosity: 1e-6,
            body_force: 2e-4,
            channel_width: 1e-3,
            sweep: 1,
        }
    }
}

impl CaseParams for PoiseuilleParams {
    const INFO: &'static [ParamInfo] = &[
        ParamInfo::new("spacing", "m", "particle spacing dp"),
        ParamInfo::new("viscosity", "m^2/s", "kinematic viscosity nu"),
        ParamInfo::new("body_force", "m/s^2", "driving body force F"),
        ParamInfo::new("channel_width", "m", "channel width L"),
        ParamInfo::new("sweep", "-", "extra coarser runs (spacing x 1.5^k)"),
    ];
    fn apply_mode(&mut self, mode: Mode) {
        match mode {
            Mode::Quick => {
                self.spacing = 1e-3 / 16.0;
                self.sweep = 0;
            }
            // L / 24 without the coarser sweep run, for the 20-minute budget of the default
            // run; the earlier default, L / 30 and one coarser run (~22 s), is
            // `--set spacing=3.3333e-5 --set sweep=1`.
            Mode::Default => {
                self.spacing = 1e-3 / 24.0;
                self.sweep = 0;
            }
            Mode::Full => {
                self.spacing = 1e-3 / 40.0;
                self.sweep = 2;
            }
        }
    }
}

const TAUS: [f64; 4] = [0.0225, 0.045, 0.1125, 1.0];

struct Outcome {
    errors: [f64; 4],
    steps: u64,
    series: Series,
}

fn simulate(p: &PoiseuilleParams, dp: f64, ctx: Option<&RunContext>) -> anyhow::Result<Outcome> {
    let l = p.channel_width;
    anyhow::ensure!(l > 0.0, "parameter `channel_width` must be > 0, got {l}");
    anyhow::ensure!(
        dp > 0.0 && dp <= l / 8.0,
        "parameter `spacing` must be in (0, L/8], got {dp}"
    );
    anyhow::ensure!(p.viscosity > 0.0, "parameter `viscosity` must be > 0");
    let nz = (l / dp).round() as usize;
    let dp = l / nz as f64;
    let nu = p.viscosity;
    let v0 = p.body_force * l * l / (8.0 * nu);
    let h_over_dp = SphSettings::default().h_over_dp;
    let per = slab_layers(h_over_dp) as f64 * dp;
    let settings = SphSettings {
        spacing: dp,
        h_over_dp,
        // resolved viscous flow: no artificial viscosity (Morris et al. 1997)
        artificial_viscosity: 0.0,
        rho0: 1000.0,
        viscosity: nu * 1000.0,
        sound_speed: sound_speed_for(v0, l, p.body_force, nu, 0.01)?,
        xsph: 0.0,
        gravity: [0.0; 3],
        body_force: [p.body_force, 0.0, 0.0],
        domain_lower: [0.0; 3],
        domain_upper: [per, per, l],
        periodic: [true, true, false],
        ..SphSettings::default()
    };
    let mut b = SphBuilder::new(settings)?;
    b.add_fluid_box([0.0; 3], [per, per, l], None)?;
    b.add_tank(
        [0.0; 3],
        [per, per, l],
        wall_layers(h_over_dp),
        [false, false, false, false, true, true],
        0,
    )?;
    let mut sys = b.build()?;
    let t_of = |tau: f64| tau * l * l / nu;
    let mut errors = [0.0; 4];
    let mut series = Series::new([
        "z_over_L",
        "v_tau0.0225",
        "v_tau0.045",
        "v_tau0.1125",
        "v_steady",
        "exact_0.0225",
        "exact_0.045",
        "exact_0.1125",
        "exact_steady",
    ]);
    let mut table = vec![vec![0.0; 9]; nz];
    for (k, &tau) in TAUS.iter().enumerate() {
        let t_end = t_of(tau);
        while sys.time() < t_end - 1e-15 {
            // do not overshoot the sampling time by more than a step
            sys.step()?;
            if let Some(c) = ctx {
                c.progress(sys.time() / t_of(1.0));
            }
        }
        let d = sys.data();
        let (mut sum, mut cnt) = (vec![0.0; nz], vec![0usize; nz]);
        for i in 0..d.len() {
            if d.kind[i] == chrono_sph::data::FLUID {
                let layer = ((d.z[i] / dp).floor().max(0.0) as usize).min(nz - 1);
                sum[layer] += d.vx[i];
                cnt[layer] += 1;
            }
        }
        let t = sys.time();
        let (mut v, mut e) = (Vec::new(), Vec::new());
        for j in 0..nz {
            let z = (j as f64 + 0.5) * dp;
            let vs = if cnt[j] > 0 {
                sum[j] / cnt[j] as f64
            } else {
                0.0
            };
            let ve = poiseuille_startup(z, t, l, nu, p.body_force, 200);
            v.push(vs);
            e.push(ve);
            table[j][0] = z / l;
            table[j][1 + k] = vs / v0;
            table[j][5 + k] = ve / v0;
        }
        errors[k] = rel_l2(&v, &e);
    }
    for row in table {
        series.push(&row);
    }
    Ok(Outcome {
        errors,
        steps: sys.steps(),
        series,
    })
}

fn run(p: &PoiseuilleParams, ctx: &RunContext) -> anyhow::Result<CaseOutput> {
    let mut out = CaseOutput::new();
    let mut conv = Vec::new();
    for dp in sweep_spacings(p.spacing, p.sweep) {
        let start = Instant::now();
        let o = simulate(p, dp, None)?;
        let e = o.errors.iter().cloned().fold(0.0, f64::max);
        out.sweep
            .push(sweep_point(dp, e, start.elapsed().as_secs_f64()));
        conv.push((dp, e));
    }
    let start = Instant::now();
    let o = simulate(p, p.spacing, Some(ctx))?;
    let worst = o.errors.iter().cloned().fold(0.0, f64::max);
    if p.sweep > 0 {
        out.sweep
            .push(sweep_point(p.spacing, worst, start.elapsed().as_secs_f64()));
        conv.push((p.spacing, worst));
        let order = convergence_order(&conv);
        out.metric("convergence_order", order);
        // the error must decrease under refinement
        out.check(Check::below(
            "error_ratio_fine_over_coarse",
            worst / conv[0].1,
            1.0,
        ));
    }
    for (k, tau) in TAUS.iter().enumerate() {
        out.metric(format!("profile_error_tau{tau}"), o.errors[k]);
    }
    out.check(Check::below("profile_error", worst, 0.03));
    out.series = o.series;
    out.plot = PlotSpec::new(
        "SPH start-up Poiseuille",
        "z / L",
        "v / v0",
        &["v_tau0.0225", "v_tau0.045", "v_tau0.1125", "v_steady"],
    )
    .with_reference(&[
        "exact_0.0225",
        "exact_0.045",
        "exact_0.1125",
        "exact_steady",
    ]);
    out.steps = o.steps;
    Ok(out)
}

/// The `sph-poiseuille` case.
pub fn case() -> Box<dyn Case> {
    ParamCase::<PoiseuilleParams>::boxed(
        "sph-poiseuille",
        "sph",
        "Start-up plane Poiseuille flow driven by a body force (Morris, Fox and Zhu 1997) against the transient series solution.",
        run,
    )
}
