//! Natural frequencies of a supported mesh about its current configuration.
//!
//! The generalized symmetric eigenproblem `K v = omega^2 M v` on the free coordinates,
//! with `K` the tangent stiffness at the current configuration and `M` the consistent
//! mass. Solved densely (nalgebra): with `M = L L^T` (Cholesky),
//! `C = L^-1 K L^-T` is symmetric with the same eigenvalues `omega^2`. Dense is fine for
//! the small meshes of the benchmarks; meshes with more than
//! [`MAX_DENSE_DOF`] free coordinates are rejected.

use nalgebra::DMatrix;

use crate::error::{FeaError, Result};
use crate::mesh::{CableMesh, DofMap, SparseMatrix};
use crate::statics::StaticModel;
use crate::tet_mesh::TetMesh;

/// A [`StaticModel`] with a mass matrix: what [`natural_frequencies`] needs.
pub trait MassModel: StaticModel {
    /// The consistent mass matrix on the free coordinates of `map`, kg.
    fn mass_matrix(&self, map: &DofMap) -> Result<SparseMatrix>;
}

impl MassModel for CableMesh {
    fn mass_matrix(&self, map: &DofMap) -> Result<SparseMatrix> {
        CableMesh::mass_matrix(self, map)
    }
}

impl MassModel for crate::beam_mesh::BeamMesh {
    fn mass_matrix(&self, map: &DofMap) -> Result<SparseMatrix> {
        crate::beam_mesh::BeamMesh::mass_matrix(self, map)
    }
}

impl MassModel for TetMesh {
    fn mass_matrix(&self, map: &DofMap) -> Result<SparseMatrix> {
        TetMesh::mass_matrix(self, map)
    }
}

/// Largest number of free coordinates [`natural_frequencies`] accepts.
pub const MAX_DENSE_DOF: usize = 3000;

fn dense(m: &faer::sparse::SparseColMat<usize, f64>) -> DMatrix<f64> {
    let mut d = DMatrix::zeros(m.nrows(), m.ncols());
    let sym = m.symbolic();
    let vals = m.val();
    for j in 0..m.ncols() {
        for idx in sym.col_range(j) {
            d[(sym.row_idx()[idx], j)] += vals[idx];
        }
    }
    d
}

/// The natural frequencies `omega / (2 pi)` (Hz) of `mesh` about its current
/// configuration, ascending. Errors: no free coordinate, too many for the dense solver, a
/// mass matrix that is not positive definite.
pub fn natural_frequencies<M: MassModel + ?Sized>(mesh: &M) -> Result<Vec<f64>> {
    let map = mesh.dof_map();
    let n = map.nfree();
    if n == 0 {
        return Err(FeaError::invalid(
            "mesh",
            "all coordinates fixed",
            "needs a free coordinate",
        ));
    }
    if n > MAX_DENSE_DOF {
        return Err(FeaError::invalid(
            "mesh.free_dof",
            n,
            format!("at most {MAX_DENSE_DOF} for the dense eigen solver"),
        ));
    }
    let q = mesh.coordinates();
    let (_, k) = mesh.internal_force(&q, &map, true)?;
    let k = dense(&k.expect("tangent requested"));
    let m = dense(&mesh.mass_matrix(&map)?);
    let chol = m.cholesky().ok_or_else(|| FeaError::Singular {
        step: 0,
        detail: "the mass matrix is not positive definite".into(),
    })?;
    let l = chol.l();
    // C = L^-1 K L^-T, by two triangular solves.
    let y = l
        .solve_lower_triangular(&k)
        .ok_or_else(|| FeaError::Singular {
            step: 0,
            detail: "Cholesky factor singular".into(),
        })?;
    let c = l
        .solve_lower_triangular(&y.transpose())
        .ok_or_else(|| FeaError::Singular {
            step: 0,
            detail: "Cholesky factor singular".into(),
        })?;
    let c = 0.5 * (&c + c.transpose());
    let eig = c.symmetric_eigenvalues();
    let mut f: Vec<f64> = eig
        .iter()
        .map(|&w2| w2.max(0.0).sqrt() / (2.0 * std::f64::consts::PI))
        .collect();
    f.sort_by(f64::total_cmp);
    Ok(f)
}
