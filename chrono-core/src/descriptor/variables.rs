//! Variable blocks: generalized velocities with their mass operators.

use std::sync::Arc;

use nalgebra::{Matrix3, UnitQuaternion, Vector3};
use rayon::prelude::*;

use super::coupled::CoupledMass;
use crate::error::{ChronoError, Result, check_positive};

/// Index of a variable block in [`Variables`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct BlockId(pub u32);

/// The mass operator of one variable block: applies `M` and `M^-1` to the block's velocities.
///
/// Equality compares the particle and rigid-body data by value and coupled blocks by
/// identity (the same shared operator).
#[derive(Debug, Clone)]
pub enum MassOperator {
    /// A point mass: 3 dof (world-frame linear velocity), mass in kg.
    Particle {
        /// Mass, kg.
        mass: f64,
    },
    /// A scalar block: 1 dof with a positive scalar mass (e.g. a shaft's spin with its
    /// polar inertia in kg m^2, a slider's speed with its mass in kg): `M = mass`.
    Scalar {
        /// Mass (kg) or polar moment of inertia (kg m^2) of the one dof.
        mass: f64,
    },
    /// A rigid body: 6 dof `[v; w]`, linear velocity `v` in the world frame (m/s) and angular
    /// velocity `w` in the body frame (rad/s); `M = diag(m I, J)` with `J` the constant
    /// body-frame inertia tensor about the center of mass (kg m^2).
    RigidBody {
        /// Mass, kg.
        mass: f64,
        /// Body-frame inertia tensor about the center of mass, kg m^2.
        inertia: Matrix3<f64>,
        /// Its inverse (cached).
        inv_inertia: Matrix3<f64>,
    },
    /// A coupled block of `n` dof with a full symmetric positive definite operator `H`
    /// (kg; for an implicit item the iteration matrix `M + h R + h^2 K`, see
    /// [`CoupledMass`]), applied by a factorization the domain crate supplies. A row's
    /// entry on such a block has `n` coefficients, and `H^-1 D_i` is dense over the block.
    Coupled(Arc<dyn CoupledMass>),
}

impl PartialEq for MassOperator {
    fn eq(&self, other: &Self) -> bool {
        use MassOperator::*;
        match (self, other) {
            (Particle { mass: a }, Particle { mass: b }) => a == b,
            (Scalar { mass: a }, Scalar { mass: b }) => a == b,
            (
                RigidBody {
                    mass: a,
                    inertia: ja,
                    ..
                },
                RigidBody {
                    mass: b,
                    inertia: jb,
                    ..
                },
            ) => a == b && ja == jb,
            (Coupled(a), Coupled(b)) => Arc::ptr_eq(a, b),
            _ => false,
        }
    }
}

impl MassOperator {
    /// A particle of mass `mass` (kg, finite and > 0).
    pub fn particle(mass: f64) -> Result<Self> {
        check_positive("mass", mass)?;
        Ok(MassOperator::Particle { mass })
    }

    /// A 1-dof scalar block of mass or inertia `mass` (finite and > 0), see
    /// [`MassOperator::Scalar`].
    pub fn scalar(mass: f64) -> Result<Self> {
        check_positive("mass", mass)?;
        Ok(MassOperator::Scalar { mass })
    }

    /// A rigid body of mass `mass` and body-frame inertia `inertia`, which must be finite,
    /// symmetric and positive definite.
    pub fn rigid_body(mass: f64, inertia: Matrix3<f64>) -> Result<Self> {
        check_positive("mass", mass)?;
        let inv_inertia = check_inertia("inertia", &inertia)?;
        Ok(MassOperator::RigidBody {
            mass,
            inertia,
            inv_inertia,
        })
    }

    /// A coupled block (see [`MassOperator::Coupled`]); its `ndof` must be >= 1.
    pub fn coupled(op: Arc<dyn CoupledMass>) -> Result<Self> {
        if op.ndof() == 0 {
            return Err(ChronoError::invalid("coupled mass ndof", 0, "must be >= 1"));
        }
        Ok(MassOperator::Coupled(op))
    }

    /// Number of degrees of freedom of the block.
    #[inline]
    pub fn ndof(&self) -> usize {
        match self {
            MassOperator::Particle { .. } => 3,
            MassOperator::Scalar { .. } => 1,
            MassOperator::RigidBody { .. } => 6,
            MassOperator::Coupled(op) => op.ndof(),
        }
    }

    /// `out = M^-1 x` for this block (`x` and `out` of length `ndof`).
    #[inline]
    pub fn apply_inverse(&self, x: &[f64], out: &mut [f64]) {
        match self {
            MassOperator::Particle { mass } => {
                let im = 1.0 / mass;
                out[0] = x[0] * im;
                out[1] = x[1] * im;
                out[2] = x[2] * im;
            }
            MassOperator::Scalar { mass } => out[0] = x[0] / mass,
            MassOperator::RigidBody {
                mass, inv_inertia, ..
            } => rigid_inverse(
                *mass,
                inv_inertia,
                x[..6].try_into().expect("6 dof"),
                (&mut out[..6]).try_into().expect("6 dof"),
            ),
            MassOperator::Coupled(op) => op.apply_inverse(x, out),
        }
    }

    /// `out = M x` for this block.
    #[inline]
    pub fn apply(&self, x: &[f64], out: &mut [f64]) {
        match self {
            MassOperator::Particle { mass } => {
                out[0] = x[0] * mass;
                out[1] = x[1] * mass;
                out[2] = x[2] * mass;
            }
            MassOperator::Scalar { mass } => out[0] = x[0] * mass,
            MassOperator::RigidBody { mass, inertia, .. } => {
                out[0] = x[0] * mass;
                out[1] = x[1] * mass;
                out[2] = x[2] * mass;
                let l = inertia * Vector3::new(x[3], x[4], x[5]);
                out[3] = l.x;
                out[4] = l.y;
                out[5] = l.z;
            }
            MassOperator::Coupled(op) => op.apply(x, out),
        }
    }
}

/// `out = M^-1 x` of a rigid body's 6 dof: `x_v / m` and `J^-1 x_w` (world frame), as
/// [`MassOperator::apply_inverse`] computes it (the assembly's fixed-size path calls it too).
#[inline(always)]
pub(crate) fn rigid_inverse(
    mass: f64,
    inv_inertia: &Matrix3<f64>,
    x: &[f64; 6],
    out: &mut [f64; 6],
) {
    let im = 1.0 / mass;
    out[0] = x[0] * im;
    out[1] = x[1] * im;
    out[2] = x[2] * im;
    let w = inv_inertia * Vector3::new(x[3], x[4], x[5]);
    out[3] = w.x;
    out[4] = w.y;
    out[5] = w.z;
}

/// Check an inertia tensor (finite, symmetric, positive definite); returns its inverse.
pub(crate) fn check_inertia(field: &str, j: &Matrix3<f64>) -> Result<Matrix3<f64>> {
    let show = || format!("{:?}", j.as_slice());
    if j.iter().any(|x| !x.is_finite()) {
        return Err(ChronoError::invalid(field, show(), "must be finite"));
    }
    let asym = (j - j.transpose()).abs().max();
    if asym > 1e-12 * j.abs().max() {
        return Err(ChronoError::invalid(field, show(), "must be symmetric"));
    }
    if j.cholesky().is_none() {
        return Err(ChronoError::invalid(
            field,
            show(),
            "must be positive definite",
        ));
    }
    j.try_inverse()
        .ok_or_else(|| ChronoError::invalid(field, show(), "must be invertible"))
}

#[derive(Debug, Clone, PartialEq)]
struct Block {
    offset: usize,
    mass: MassOperator,
    /// A rigid body's orientation (body to world), if given ([`Variables::add_oriented`]).
    rotation: Option<UnitQuaternion<f64>>,
}

/// A run of consecutive blocks with the same number of dof, so that block-wise operations
/// can be done in parallel over uniform chunks of the velocity vector.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Run {
    /// The first block of the run.
    pub first_block: usize,
    /// Number of blocks.
    pub n_blocks: usize,
    /// Dof of each block of the run.
    pub ndof: usize,
    /// First dof of the run: the run owns `v[dof_offset .. dof_offset + n_blocks * ndof]`.
    pub dof_offset: usize,
}

/// All variable blocks of a step, laid out contiguously: block `i` owns
/// `v[offset(i) .. offset(i) + ndof(i)]`.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Variables {
    blocks: Vec<Block>,
    runs: Vec<Run>,
    ndof: usize,
}

/// Below this many dof, block-wise loops run sequentially (rayon's overhead would dominate).
const PAR_MIN_DOF: usize = 8192;

impl Variables {
    /// An empty set.
    pub fn new() -> Self {
        Self::default()
    }

    /// Make this set a copy of `src`, reusing this set's allocations (the blocks copied in
    /// parallel for many dof). The same value as `src.clone()`.
    pub fn copy_from(&mut self, src: &Variables) {
        self.blocks.clear();
        if src.ndof >= PAR_MIN_DOF {
            self.blocks.par_extend(src.blocks.par_iter().cloned());
        } else {
            self.blocks.extend_from_slice(&src.blocks);
        }
        self.runs.clone_from(&src.runs);
        self.ndof = src.ndof;
    }

    /// Remove all blocks, keeping the allocations.
    pub fn clear(&mut self) {
        self.blocks.clear();
        self.runs.clear();
        self.ndof = 0;
    }

    /// Append a block; returns its id.
    pub fn add(&mut self, mass: MassOperator) -> BlockId {
        self.push_block(mass, None)
    }

    /// Append a rigid body's block with its orientation `R` (body to world: the angular
    /// velocity of the block is `R' w_world`); returns its id. With it the rows of the
    /// crate's contacts on the block can be stored as their geometry alone and rebuilt
    /// when needed (`[d; (R' r) x (R' d)]`, see `ContactFrame`). Also valid for any
    /// other block (the rotation is then ignored).
    pub fn add_oriented(&mut self, mass: MassOperator, rotation: UnitQuaternion<f64>) -> BlockId {
        self.push_block(mass, Some(rotation))
    }

    /// The orientation given with [`add_oriented`](Self::add_oriented), if any.
    #[inline]
    pub fn rotation(&self, id: BlockId) -> Option<&UnitQuaternion<f64>> {
        self.blocks[id.0 as usize].rotation.as_ref()
    }

    fn push_block(&mut self, mass: MassOperator, rotation: Option<UnitQuaternion<f64>>) -> BlockId {
        let ndof = mass.ndof();
        let id = self.blocks.len();
        match self.runs.last_mut() {
            Some(run) if run.ndof == ndof => run.n_blocks += 1,
            _ => self.runs.push(Run {
                first_block: id,
                n_blocks: 1,
                ndof,
                dof_offset: self.ndof,
            }),
        }
        self.blocks.push(Block {
            offset: self.ndof,
            mass,
            rotation,
        });
        self.ndof += ndof;
        BlockId(id as u32)
    }

    /// Total number of dof.
    #[inline]
    pub fn ndof(&self) -> usize {
        self.ndof
    }

    /// Number of blocks.
    #[inline]
    pub fn len(&self) -> usize {
        self.blocks.len()
    }

    /// True if there are no blocks.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.blocks.is_empty()
    }

    /// First dof of a block.
    #[inline]
    pub fn offset(&self, id: BlockId) -> usize {
        self.blocks[id.0 as usize].offset
    }

    /// Number of dof of a block.
    #[inline]
    pub fn block_ndof(&self, id: BlockId) -> usize {
        self.blocks[id.0 as usize].mass.ndof()
    }

    /// The mass operator of a block.
    #[inline]
    pub fn mass(&self, id: BlockId) -> &MassOperator {
        &self.blocks[id.0 as usize].mass
    }

    /// The dof range of a block.
    #[inline]
    pub fn range(&self, id: BlockId) -> std::ops::Range<usize> {
        let b = &self.blocks[id.0 as usize];
        b.offset..b.offset + b.mass.ndof()
    }

    /// The runs of consecutive blocks with equal dof counts, in block order (they cover
    /// all blocks): a velocity vector splits into uniform chunks per run, e.g. for
    /// block-parallel loops with `par_chunks_mut(run.ndof)`.
    pub fn runs(&self) -> &[Run] {
        &self.runs
    }

    /// `out = M^-1 x` over all blocks (parallel for large systems).
    pub fn apply_inverse(&self, x: &[f64], out: &mut [f64]) {
        self.blockwise(x, out, |m, xi, oi| m.apply_inverse(xi, oi));
    }

    /// `out = M x` over all blocks.
    pub fn apply(&self, x: &[f64], out: &mut [f64]) {
        self.blockwise(x, out, |m, xi, oi| m.apply(xi, oi));
    }

    fn blockwise(
        &self,
        x: &[f64],
        out: &mut [f64],
        f: impl Fn(&MassOperator, &[f64], &mut [f64]) + Sync,
    ) {
        assert_eq!(x.len(), self.ndof, "x has the wrong length");
        assert_eq!(out.len(), self.ndof, "out has the wrong length");
        for run in &self.runs {
            let r = run.dof_offset..run.dof_offset + run.n_blocks * run.ndof;
            let blocks = &self.blocks[run.first_block..run.first_block + run.n_blocks];
            if self.ndof >= PAR_MIN_DOF {
                out[r.clone()]
                    .par_chunks_mut(run.ndof)
                    .zip(x[r].par_chunks(run.ndof))
                    .zip(blocks.par_iter())
                    .for_each(|((o, xi), b)| f(&b.mass, xi, o));
            } else {
                for ((o, xi), b) in out[r.clone()]
                    .chunks_mut(run.ndof)
                    .zip(x[r].chunks(run.ndof))
                    .zip(blocks)
                {
                    f(&b.mass, xi, o);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn inverse_undoes_apply() {
        let mut vars = Variables::new();
        let j = Matrix3::new(2.0, 0.1, 0.0, 0.1, 3.0, 0.2, 0.0, 0.2, 4.0);
        vars.add(MassOperator::particle(2.0).unwrap());
        vars.add(MassOperator::rigid_body(5.0, j).unwrap());
        vars.add(MassOperator::particle(0.5).unwrap());
        assert_eq!(vars.ndof(), 12);
        assert_eq!(vars.runs().len(), 3);
        let x: Vec<f64> = (0..12).map(|i| i as f64 - 3.5).collect();
        let mut mx = vec![0.0; 12];
        let mut back = vec![0.0; 12];
        vars.apply(&x, &mut mx);
        vars.apply_inverse(&mx, &mut back);
        for i in 0..12 {
            assert!((back[i] - x[i]).abs() < 1e-12);
        }
    }

    #[test]
    fn scalar_blocks_have_one_dof_between_other_blocks() {
        let mut vars = Variables::new();
        vars.add(MassOperator::particle(2.0).unwrap());
        let s0 = vars.add(MassOperator::scalar(0.5).unwrap());
        let s1 = vars.add(MassOperator::scalar(4.0).unwrap());
        vars.add(MassOperator::particle(3.0).unwrap());
        assert_eq!(vars.ndof(), 8);
        assert_eq!(vars.range(s0), 3..4);
        assert_eq!(vars.range(s1), 4..5);
        assert_eq!(vars.runs().len(), 3);
        assert_eq!(vars.runs()[1].ndof, 1);
        assert_eq!(vars.runs()[1].n_blocks, 2);
        let x = [1.0, -2.0, 3.0, 1.5, -2.0, 0.5, 0.25, -1.0];
        let (mut mx, mut back) = ([0.0; 8], [0.0; 8]);
        vars.apply(&x, &mut mx);
        assert_eq!(mx[3], 0.75);
        assert_eq!(mx[4], -8.0);
        vars.apply_inverse(&mx, &mut back);
        for i in 0..8 {
            assert!((back[i] - x[i]).abs() < 1e-15, "{i}");
        }
        let e = MassOperator::scalar(-1.0).unwrap_err().to_string();
        assert!(e.contains("mass") && e.contains("-1"), "{e}");
        assert!(MassOperator::scalar(f64::NAN).is_err());
    }

    #[test]
    fn coupled_block_beside_particles() {
        use crate::descriptor::DenseMass;
        use nalgebra::DMatrix;
        // A 4-dof SPD block between two particles: offsets, runs and both operators.
        let h = DMatrix::from_row_slice(
            4,
            4,
            &[
                4.0, 1.0, 0.0, 0.5, 1.0, 3.0, 0.2, 0.0, 0.0, 0.2, 2.0, 0.1, 0.5, 0.0, 0.1, 5.0,
            ],
        );
        let op: Arc<dyn CoupledMass> = Arc::new(DenseMass::new(h.clone()).unwrap());
        let mut vars = Variables::new();
        vars.add(MassOperator::particle(2.0).unwrap());
        let c = vars.add(MassOperator::coupled(op.clone()).unwrap());
        vars.add(MassOperator::particle(0.5).unwrap());
        assert_eq!(vars.ndof(), 10);
        assert_eq!(vars.range(c), 3..7);
        assert_eq!(vars.mass(c), &MassOperator::Coupled(op));
        let x: Vec<f64> = (0..10).map(|i| 0.3 * i as f64 - 1.0).collect();
        let (mut mx, mut back) = (vec![0.0; 10], vec![0.0; 10]);
        vars.apply(&x, &mut mx);
        let hx = &h * nalgebra::DVector::from_column_slice(&x[3..7]);
        for i in 0..4 {
            assert!((mx[3 + i] - hx[i]).abs() < 1e-14);
        }
        vars.apply_inverse(&mx, &mut back);
        for i in 0..10 {
            assert!((back[i] - x[i]).abs() < 1e-12, "{i}");
        }
    }

    #[test]
    fn rejects_bad_mass_and_inertia() {
        assert!(
            MassOperator::particle(0.0)
                .unwrap_err()
                .to_string()
                .contains("mass")
        );
        let not_pd = Matrix3::from_diagonal(&Vector3::new(1.0, -1.0, 1.0));
        let e = MassOperator::rigid_body(1.0, not_pd)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("inertia") && e.contains("positive definite"),
            "{e}"
        );
        let asym = Matrix3::new(1.0, 0.5, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0);
        assert!(
            MassOperator::rigid_body(1.0, asym)
                .unwrap_err()
                .to_string()
                .contains("symmetric")
        );
    }
}
