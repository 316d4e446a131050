//! `fea-cantilever-frequency`: the first bending frequency of an ANCF cantilever.
//!
//! The eigenproblem `K v = omega^2 M v` at the undeformed state (tangent stiffness,
//! consistent mass, clamped root; [`natural_frequencies`]) against the Euler–Bernoulli
//! cantilever `f_1 = 1.875^2 sqrt(E I / (rho A L^4)) / (2 pi)`, within 2 %.

use chrono_fea::analytic::cantilever_first_frequency;
use chrono_fea::natural_frequencies;
use serde::{Deserialize, Serialize};

use super::{Element, check_cable_only};
use crate::case::{Case, CaseOutput, Check, PlotSpec, RunContext, Series, SweepPoint};
use crate::params::{CaseParams, ParamCase, ParamInfo};
use chrono_fea::cable_cantilever;

/// Parameters of `fea-cantilever-frequency`.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct FrequencyParams {
    /// Number of elements.
    pub n_elements: usize,
    /// Beam length, m.
    pub length: f64,
    /// Young's modulus, Pa.
    pub young: f64,
    /// Density, kg/m^3.
    pub density: f64,
    /// Section width, m.
    pub width: f64,
    /// Section height (the bending direction), m.
    pub height: f64,
    /// Element type: `cable` (`beam`: not yet available).
    pub element: Element,
    /// Relative tolerance on the first frequency.
    pub tolerance: f64,
}

impl Default for FrequencyParams {
    fn default() -> Self {
        Self {
            n_elements: 8,
            length: 1.0,
            young: 2.0e11,
            density: 7850.0,
            width: 0.01,
            height: 0.01,
            element: Element::Cable,
            tolerance: 0.02,
        }
    }
}

impl CaseParams for FrequencyParams {
    const INFO: &'static [ParamInfo] = &[
        ParamInfo::new("n_elements", "-", "number of elements"),
        ParamInfo::new("length", "m", "beam length"),
        ParamInfo::new("young", "Pa", "Young's modulus"),
        ParamInfo::new("density", "kg/m^3", "density"),
        ParamInfo::new("width", "m", "section width"),
        ParamInfo::new("height", "m", "section height (bending direction)"),
        ParamInfo::new("element", "-", "element type: cable (beam: not yet)"),
        ParamInfo::new(
            "tolerance",
            "-",
            "relative tolerance on the first frequency",
        ),
    ];
}

fn first_frequency(p: &FrequencyParams, n: usize) -> anyhow::Result<f64> {
    let mesh = cable_cantilever(n, p.length, p.young, p.density, p.width, p.height)?;
    let f = natural_frequencies(&mesh)?;
    Ok(f[0])
}

fn run(p: &FrequencyParams, ctx: &RunContext) -> anyhow::Result<CaseOutput> {
    check_cable_only(p.element)?;
    let mat = chrono_fea::BeamMaterial::rectangle(p.young, p.density, p.width, p.height, 0.0)?;
    let exact =
        cantilever_first_frequency(mat.bending_stiffness(), mat.mass_per_length(), p.length);
    let mesh = cable_cantilever(
        p.n_elements,
        p.length,
        p.young,
        p.density,
        p.width,
        p.height,
    )?;
    let f = natural_frequencies(&mesh)?;
    let mut out = CaseOutput::new();
    out.check(Check::relative("first_frequency", f[0], exact, p.tolerance));
    out.metric("first_frequency_reference", exact);
    // The cable's bending stiffness is isotropic: the first two modes are the two
    // bending planes. The second bending frequency of the Euler-Bernoulli cantilever:
    // (4.694091 / 1.875104)^2 f_1 (beta_2 L = 4.694091).
    out.metric("second_mode_frequency", f[1]);
    if let Some(f3) = f.get(2) {
        out.metric("third_mode_frequency", *f3);
    }
    out.metric(
        "second_bending_frequency_reference",
        exact * (4.694_091f64 / 1.875).powi(2),
    );
    let mut series = Series::new(["n_elements", "f1_over_reference"]);
    for (i, n) in [1usize, 2, 4, 8, 16].into_iter().enumerate() {
        let start = std::time::Instant::now();
        let fi = first_frequency(p, n)?;
        series.push(&[n as f64, fi / exact]);
        out.sweep.push(SweepPoint {
            label: format!("{n} elements"),
            error: (fi / exact - 1.0).abs(),
            wall_s: start.elapsed().as_secs_f64().max(1e-9),
        });
        ctx.progress((i + 1) as f64 / 5.0);
    }
    out.series = series;
    out.plot = PlotSpec::new(
        "ANCF cantilever: first bending frequency / Euler-Bernoulli",
        "elements [-]",
        "f1 / f1_EB [-]",
        &["f1_over_reference"],
    );
    out.steps = 1;
    Ok(out)
}

/// The case.
pub fn case() -> Box<dyn Case> {
    ParamCase::<FrequencyParams>::boxed(
        "fea-cantilever-frequency",
        "fea",
        "First bending frequency of an ANCF cable cantilever (K v = w^2 M v at the undeformed state) against 1.875^2 sqrt(EI/(rho A L^4))/(2 pi), within 2 %.",
        run,
    )
}
