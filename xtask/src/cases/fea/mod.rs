//! Finite-element validation cases (chrono-fea):
//!
//! - `fea-bend-45`: the 45-degree bend of Bathe & Bolourchi (1979), a curved cantilever
//!   under an out-of-plane tip load, with the fully parameterized ANCF beam;
//! - `fea-cantilever`: an ANCF cantilever under a dead tip force, from the small-load
//!   Euler–Bernoulli regime to the large-deflection elastica (`P L^2 / (E I)` up to 10);
//! - `fea-cantilever-frequency`: its first bending frequency against the Euler–Bernoulli
//!   value `1.875^2 sqrt(E I / (rho A L^4)) / (2 pi)`;
//! - `fea-pendulum`: an undamped flexible pendulum stepped in the system's CCP (implicit
//!   Euler) keeps its energy; the numerical damping against the step size;
//! - `fea-tet-patch`: the patch test of the linear tetrahedron on a distorted mesh;
//! - `fea-tet-cantilever`: a tetrahedral box cantilever under a tip shear load, mesh
//!   convergence of the tip deflection against beam theory;
//! - `fea-shell-cantilever`: the ANCF shell plate strip under end shear against the
//!   load–displacement curve of Sze, Liu & Lo (2004);
//! - `fea-shell-pressure`: an ANCF shell sphere under internal follower pressure against
//!   the membrane solution;
//! - `fea-tire-drop`: a pressurized ANCF shell tire on a rigid rim dropped on rigid
//!   ground comes to rest: static deflection against the membrane estimate;
//! - `fea-tire-static`: the tire pressed statically on rigid ground: load–deflection at
//!   several pressures, trends and mesh convergence;
//! - `fea-tire-rolling`: the tire rolling freely under load: effective rolling radius
//!   against `(2 r_0 + r_s) / 3`.

pub mod bend45;
pub mod cantilever;
pub mod frequency;
pub mod pendulum;
pub mod shell_cantilever;
pub mod shell_pressure;
pub mod tet_cantilever;
pub mod tet_patch;
pub mod tire_drop;
pub mod tire_rolling;
pub mod tire_static;

use serde::{Deserialize, Serialize};

/// The beam element of a case parameter (`--set element=beam`): the gradient deficient
/// ANCF cable or the fully parameterized ANCF beam.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Element {
    /// The ANCF cable (`chrono_fea::cable_cantilever`).
    #[default]
    Cable,
    /// The fully parameterized ANCF beam (`chrono_fea::beam_cantilever`).
    Beam,
}

/// For the cases that only run the cable (`fea-cantilever-frequency`, `fea-pendulum`):
/// `beam` is rejected with a clear error — it runs in `fea-cantilever` and `fea-bend-45`.
pub fn check_cable_only(element: Element) -> anyhow::Result<()> {
    match element {
        Element::Cable => Ok(()),
        Element::Beam => anyhow::bail!(
            "parameter `element` = `beam`: this case runs the cable only (the fully parameterized ANCF beam runs in fea-cantilever and fea-bend-45); use `cable`"
        ),
    }
}

/// The shell locking remedies of a case parameter (`--set locking=ans`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum Locking {
    /// Assumed natural strain and enhanced assumed strain (the element's default).
    #[default]
    #[serde(rename = "ans+eas")]
    AnsEas,
    /// Assumed natural strain only.
    #[serde(rename = "ans")]
    Ans,
    /// Enhanced assumed strain only (locks).
    #[serde(rename = "eas")]
    Eas,
    /// Neither (locks).
    #[serde(rename = "none")]
    None,
}

impl Locking {
    /// The element's switches.
    pub fn remedies(self) -> chrono_fea::ShellLocking {
        let (ans, eas) = match self {
            Locking::AnsEas => (true, true),
            Locking::Ans => (true, false),
            Locking::Eas => (false, true),
            Locking::None => (false, false),
        };
        chrono_fea::ShellLocking { ans, eas }
    }
}
