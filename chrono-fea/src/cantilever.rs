//! Straight cantilevers along `+X` from the origin, clamped at node 0: the meshes of the
//! beam benchmarks (tip load, first bending frequency, the examples), for the gradient
//! deficient ANCF cable and the fully parameterized ANCF beam.
//!
//! The section is a `width` (along `Y`) x `height` (along `Z`) rectangle: bending under a
//! load along `Z` goes across the height, with `E I = E width height^3 / 12`.

use nalgebra::Vector3;

use crate::element::CableQuadrature;
use crate::error::{FeaError, Result, positive};
use crate::material::{BeamMaterial, BeamSection};
use crate::node::NodeId;
use crate::{BeamMesh, CableMesh};

/// Checks shared by both builders: at least one element, a finite positive length.
fn check(n_elements: usize, length: f64) -> Result<()> {
    if n_elements < 1 {
        return Err(FeaError::invalid("n_elements", n_elements, "must be >= 1"));
    }
    positive("length", length)?;
    Ok(())
}

/// A cantilever of `n_elements` ANCF cable elements, `length` m long, Young's modulus
/// `young` (Pa), density `density` (kg/m^3), a `width` x `height` rectangular section
/// (m), clamped at node 0 (position and slope direction). Errors name the field.
pub fn cable_cantilever(
    n_elements: usize,
    length: f64,
    young: f64,
    density: f64,
    width: f64,
    height: f64,
) -> Result<CableMesh> {
    check(n_elements, length)?;
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

/// The cantilever of [`cable_cantilever`] with the fully parameterized ANCF beam,
/// Poisson's ratio 0 (the beam-theory references are shear-rigid; the beam's shear
/// flexibility adds `~ 3 E I / (k G A L^2) ~ 1e-4` relative at `L / h = 100`), clamped at
/// node 0 (all 12 coordinates).
pub fn beam_cantilever(
    n_elements: usize,
    length: f64,
    young: f64,
    density: f64,
    width: f64,
    height: f64,
) -> Result<BeamMesh> {
    check(n_elements, length)?;
    let section = BeamSection::rectangle(young, 0.0, density, width, height)?;
    let mut mesh = BeamMesh::straight(
        Vector3::zeros(),
        Vector3::new(length, 0.0, 0.0),
        n_elements,
        Vector3::y(),
        section,
    )?;
    mesh.clamp(NodeId(0))?;
    Ok(mesh)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bad_sizes_name_the_field() {
        let e = cable_cantilever(0, 1.0, 2e11, 7850.0, 0.01, 0.01).unwrap_err();
        assert!(e.to_string().contains("n_elements"), "{e}");
        let e = beam_cantilever(4, -1.0, 2e11, 7850.0, 0.01, 0.01).unwrap_err();
        assert!(e.to_string().contains("length"), "{e}");
        assert!(cable_cantilever(4, 1.0, 2e11, 7850.0, 0.01, 0.01).is_ok());
    }
}
