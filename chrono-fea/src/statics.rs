//! Static equilibrium by Newton's method with load stepping.
//!
//! Solves `R(q) = Q(q) - lambda F - F_f(q, lambda) = 0` on the free coordinates for the
//! load factors `lambda_k = k / n`, `k = 1..n` (`F`: nodal forces and gravity of the
//! mesh, dead loads; `F_f`: follower loads such as a shell pressure, with their load
//! stiffness `dF_f/dq` subtracted from the tangent, [`StaticModel::follower_force`]),
//! starting from the mesh's current configuration. Each Newton iteration solves
//! `K(q) dq = -R(q)` with the exact tangent `K = dQ/dq` factorized by faer's sparse LU
//! (partial pivoting: the tangent may be indefinite past a limit point). A load step has
//! converged when
//!
//! ```text
//! ||R||_2 <= rtol (||lambda F||_2 + ||F_f||_2) + atol
//! ```
//!
//! (norm over the free coordinates; position rows in N, slope rows in N m — for the unit
//! slopes of the cable both are force scales). `atol` defaults to `1e-13` times the
//! model's [`force_scale`](StaticModel::force_scale) (`max E A` for a cable mesh,
//! `max (E V^(1/3)) max |X|` for a tetrahedral mesh: its stiffest element displaced by
//! the size of the coordinates): near the round-off floor of the internal force of a
//! stiff element (positions are absolute coordinates), far below any load of interest.
//!
//! Any model with coordinates, supports, loads, an internal force and its tangent can be
//! solved: the [`StaticModel`] trait, implemented by [`CableMesh`],
//! [`TetMesh`](crate::tet_mesh::TetMesh) and [`ShellMesh`](crate::shell_mesh::ShellMesh).

use faer::Mat;
use faer::prelude::*;

use crate::error::{FeaError, Result, non_negative};
#[cfg(doc)]
use crate::mesh::CableMesh;
use crate::mesh::{DofMap, SparseMatrix};

/// Implements [`StaticModel`] for a mesh type whose inherent methods `coordinates`,
/// `set_coordinates`, `dof_map`, `external_force` and `internal_force` have the trait's
/// signatures (every mesh of this crate), followed by the type's own items
/// (`force_scale`, optionally `follower_force`, ...).
macro_rules! static_model_via_inherent {
    ($ty:ty { $($rest:tt)* }) => {
        impl $crate::statics::StaticModel for $ty {
            fn coordinates(&self) -> Vec<f64> {
                <$ty>::coordinates(self)
            }
            fn set_coordinates(&mut self, q: &[f64]) -> $crate::error::Result<()> {
                <$ty>::set_coordinates(self, q)
            }
            fn dof_map(&self) -> $crate::mesh::DofMap {
                <$ty>::dof_map(self)
            }
            fn external_force(&self, lambda: f64) -> Vec<f64> {
                <$ty>::external_force(self, lambda)
            }
            fn internal_force(
                &self,
                q: &[f64],
                map: &$crate::mesh::DofMap,
                tangent: bool,
            ) -> $crate::error::Result<(Vec<f64>, Option<$crate::mesh::SparseMatrix>)> {
                <$ty>::internal_force(self, q, map, tangent)
            }
            $($rest)*
        }
    };
}
pub(crate) use static_model_via_inherent;

/// What [`solve_static`] needs of a mesh. Global coordinates are numbered by the mesh;
/// supports hold coordinates at their current values ([`DofMap`]).
pub trait StaticModel {
    /// The global coordinate vector of the current configuration.
    fn coordinates(&self) -> Vec<f64>;
    /// Set the current configuration (all coordinates).
    fn set_coordinates(&mut self, q: &[f64]) -> Result<()>;
    /// The numbering of the free coordinates.
    fn dof_map(&self) -> DofMap;
    /// The dead loads at load factor `lambda` (global vector).
    fn external_force(&self, lambda: f64) -> Vec<f64>;
    /// The internal force `Q(q)` (global) and, if `tangent`, `dQ/dq` on the free
    /// coordinates of `map`.
    fn internal_force(
        &self,
        q: &[f64],
        map: &DofMap,
        tangent: bool,
    ) -> Result<(Vec<f64>, Option<SparseMatrix>)>;
    /// A force scale of the stiffest element (N): the default absolute tolerance is
    /// `1e-13` of it.
    fn force_scale(&self) -> f64;
    /// Configuration-dependent (follower) loads at load factor `lambda`, e.g. a pressure
    /// along the deformed normal: their global force `F_f(q, lambda)` and, if `tangent`,
    /// the load stiffness `dF_f/dq` on the free coordinates of `map` (not necessarily
    /// symmetric). `None` (the default): no follower load.
    fn follower_force(
        &self,
        _q: &[f64],
        _lambda: f64,
        _map: &DofMap,
        _tangent: bool,
    ) -> Result<Option<(Vec<f64>, Option<SparseMatrix>)>> {
        Ok(None)
    }
}

/// Settings of [`solve_static`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StaticSettings {
    /// Number of equal load increments (>= 1).
    pub load_steps: usize,
    /// Newton iteration cap per load step (>= 1).
    pub max_iterations: usize,
    /// Relative residual tolerance (to the applied load norm).
    pub relative_tolerance: f64,
    /// Absolute residual tolerance, N; `None`: `1e-13` of the model's
    /// [`force_scale`](StaticModel::force_scale).
    pub absolute_tolerance: Option<f64>,
}

impl Default for StaticSettings {
    fn default() -> Self {
        Self {
            load_steps: 10,
            max_iterations: 30,
            relative_tolerance: 1e-10,
            absolute_tolerance: None,
        }
    }
}

/// What a static solve did.
#[derive(Debug, Clone, PartialEq)]
pub struct StaticReport {
    /// Newton iterations of each load step.
    pub iterations: Vec<usize>,
    /// Residual norm at the end of the last step, N.
    pub residual: f64,
    /// The tolerance the last step reached, N.
    pub tolerance: f64,
}

impl StaticReport {
    /// Total Newton iterations (= tangent factorizations).
    pub fn total_iterations(&self) -> usize {
        self.iterations.iter().sum()
    }
}

fn norm(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

/// Bring `mesh` to static equilibrium under its loads (see the module docs). The mesh
/// keeps the converged configuration; on an error it keeps the last converged step.
pub fn solve_static<M: StaticModel + ?Sized>(
    mesh: &mut M,
    settings: &StaticSettings,
) -> Result<StaticReport> {
    if settings.load_steps == 0 {
        return Err(FeaError::invalid("statics.load_steps", 0, "must be >= 1"));
    }
    if settings.max_iterations == 0 {
        return Err(FeaError::invalid(
            "statics.max_iterations",
            0,
            "must be >= 1",
        ));
    }
    non_negative("statics.relative_tolerance", settings.relative_tolerance)?;
    let atol = match settings.absolute_tolerance {
        Some(a) => non_negative("statics.absolute_tolerance", a)?,
        None => 1e-13 * mesh.force_scale(),
    };
    if settings.relative_tolerance == 0.0 && atol == 0.0 {
        return Err(FeaError::invalid(
            "statics.absolute_tolerance",
            0,
            "relative and absolute tolerance cannot both be 0",
        ));
    }
    let map = mesh.dof_map();
    let n = settings.load_steps;
    let mut q = mesh.coordinates();
    let mut report = StaticReport {
        iterations: Vec::with_capacity(n),
        residual: 0.0,
        tolerance: atol,
    };
    for step in 1..=n {
        let lambda = step as f64 / n as f64;
        let fext = map.restrict(&mesh.external_force(lambda));
        let mut tol = settings.relative_tolerance * norm(&fext) + atol;
        let mut q_trial = q.clone();
        let mut iterations = 0;
        let mut residual;
        loop {
            let (fint, mut k) = mesh.internal_force(&q_trial, &map, true)?;
            let mut r: Vec<f64> = map
                .restrict(&fint)
                .iter()
                .zip(&fext)
                .map(|(a, b)| a - b)
                .collect();
            if let Some((ff, kf)) = mesh.follower_force(&q_trial, lambda, &map, true)? {
                let ff = map.restrict(&ff);
                for (ri, fi) in r.iter_mut().zip(&ff) {
                    *ri -= fi;
                }
                // The follower load counts in the relative tolerance like a dead load.
                tol = settings.relative_tolerance * (norm(&fext) + norm(&ff)) + atol;
                if let (Some(kk), Some(kf)) = (k.as_ref(), kf) {
                    k = Some(
                        faer::sparse::ops::sub(kk.as_ref(), kf.as_ref())
                            .map_err(|e| FeaError::Assembly(format!("{e:?}")))?,
                    );
                }
            }
            residual = norm(&r);
            if !residual.is_finite() {
                return Err(FeaError::NonFinite {
                    step,
                    quantity: "residual",
                });
            }
            if residual <= tol {
                break;
            }
            if iterations == settings.max_iterations {
                return Err(FeaError::NotConverged {
                    step,
                    steps: n,
                    load_factor: lambda,
                    residual,
                    tolerance: tol,
                    iterations,
                });
            }
            let k = k.expect("tangent requested");
            let lu = k.sp_lu().map_err(|e| FeaError::Singular {
                step,
                detail: e.to_string(),
            })?;
            let mut rhs = Mat::<f64>::from_fn(r.len(), 1, |i, _| -r[i]);
            lu.solve_in_place(rhs.as_mut());
            // Partial pivoting does not report a singular tangent (a mechanism: missing
            // supports); it shows as a non-finite correction.
            if (0..rhs.nrows()).any(|i| !rhs[(i, 0)].is_finite()) {
                return Err(FeaError::Singular {
                    step,
                    detail: "the Newton correction is not finite (is the mesh supported?)".into(),
                });
            }
            for (g, slot) in q_trial.iter_mut().enumerate() {
                if let Some(i) = map.free_index(g) {
                    *slot += rhs[(i, 0)];
                }
            }
            iterations += 1;
        }
        q = q_trial;
        mesh.set_coordinates(&q).map_err(|_| FeaError::NonFinite {
            step,
            quantity: "coordinates",
        })?;
        report.iterations.push(iterations);
        report.residual = residual;
        report.tolerance = tol;
    }
    Ok(report)
}
