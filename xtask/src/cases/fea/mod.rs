//! Finite-element validation cases (chrono-fea):
//!
//! - `fea-cantilever`: an ANCF cantilever under a dead tip force, from the small-load
//!   Euler–Bernoulli regime to the large-deflection elastica (`P L^2 / (E I)` up to 10);
//! - `fea-cantilever-frequency`: its first bending frequency against the Euler–Bernoulli
//!   value `1.875^2 sqrt(E I / (rho A L^4)) / (2 pi)`;
//! - `fea-pendulum`: an undamped flexible pendulum stepped in the system's CCP (implicit
//!   Euler) keeps its energy; the numerical damping against the step size.

pub mod cantilever;
pub mod frequency;
pub mod pendulum;

use chrono_core::math::Vector3;
use chrono_fea::{BeamMaterial, CableMesh, CableQuadrature, NodeId};

/// The beam element of a case parameter: only `cable` (the gradient-deficient ANCF
/// cable/beam) exists so far.
pub fn check_element(element: &str) -> anyhow::Result<()> {
    match element {
        "cable" => Ok(()),
        "beam" => anyhow::bail!(
            "parameter `element` = `beam`: the fully parameterized ANCF beam is not implemented yet; use `cable`"
        ),
        other => {
            anyhow::bail!("parameter `element` must be `cable` (or, later, `beam`), got `{other}`")
        }
    }
}

/// A straight cantilever along +X from the origin, clamped at node 0 (position and slope direction),
/// `n_elements` cable elements of a rectangular `width` x `height` section (bending
/// across the height, which lies along Z).
pub fn cantilever_mesh(
    n_elements: usize,
    length: f64,
    young: f64,
    density: f64,
    width: f64,
    height: f64,
) -> anyhow::Result<CableMesh> {
    anyhow::ensure!(
        n_elements >= 1,
        "parameter `n_elements` must be >= 1, got {n_elements}"
    );
    anyhow::ensure!(
        length.is_finite() && length > 0.0,
        "parameter `length` must be > 0, got {length}"
    );
    let material = BeamMaterial::rectangle(young, density, width, height, 0.0)?;
    let mut mesh = CableMesh::straight(
        Vector3::zeros(),
        Vector3::new(length, 0.0, 0.0),
        n_elements,
        material,
        CableQuadrature::default(),
    )?;
    mesh.clamp(NodeId(0))?;
    Ok(mesh)
}
