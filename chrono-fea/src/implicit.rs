//! The state and bookkeeping shared by the implicit mesh items ([`CableItem`],
//! [`TetItem`], [`ShellItem`]): the coupled block of a mesh in the system's CCP.
//!
//! Every item steps its mesh with the linearized implicit Euler of
//! [`dynamics`](crate::dynamics),
//!
//! ```text
//! (M + h R + h^2 K) v+ = M v + h f(q) + D gamma,     q+ = q + h v+
//! ```
//!
//! and differs only in its elements (how `f` and `K` are computed) and in how a node's
//! coordinates are laid out. [`ImplicitBlock`] holds what does not depend on that: the
//! numbering of the free coordinates, the consistent mass on them, the iteration matrix
//! `H` with its fixed sparse pattern and Cholesky factorization ([`SparseSpd`]), the
//! element-to-pattern scatter map (so a step allocates nothing), the velocities, the
//! attachment rows and the contact-proxy Jacobian scratch.
//!
//! [`CableItem`]: crate::CableItem
//! [`TetItem`]: crate::TetItem
//! [`ShellItem`]: crate::ShellItem

use std::sync::{Arc, Mutex};

use chrono_core::descriptor::{
    BlockId, CcpProblem, ConstraintRows, MassOperator, RowId, Variables,
};
use chrono_core::item::StepContext;
use chrono_core::{ChronoError, Result as CoreResult};
use faer::sparse::{SparseColMat, Triplet};
use nalgebra::Vector3;

use crate::attach_rows::{AttachContext, push_attachment_rows};
use crate::dynamics::{AttachTarget, Attachment};
use crate::error::{FeaError, Result, finite3};
use crate::mesh::DofMap;
use crate::node::NodeId;
use crate::spd::{SparseSpd, symmetric_upper_mul};

const NONE: usize = usize::MAX;

/// The coupled block of an implicit mesh item (see the module docs).
#[derive(Debug)]
pub(crate) struct ImplicitBlock {
    /// The item's name for messages: `FEA item "<name>"`.
    pub label: String,
    pub map: DofMap,
    /// Global coordinate of each free index.
    pub free_global: Vec<usize>,
    /// Velocities of all coordinates (0 on the supported ones).
    pub velocity: Vec<f64>,
    op: Arc<SparseSpd>,
    /// Consistent mass on the free coordinates (upper triangle, the pattern of `op`).
    pub mass: SparseColMat<usize, f64>,
    /// Coordinates per element.
    el_ndof: usize,
    /// For element `e` and local pair `(a, b)`: the index of the upper-triangle value it
    /// adds to (`NONE`: a supported coordinate or the lower triangle).
    scatter: Vec<usize>,
    h_values: Vec<f64>,
    /// `f(q)` at the start of the step (all coordinates): applied loads, gravity, minus
    /// the internal force.
    pub force: Vec<f64>,
    /// The coordinates at the start of the step (all), updated by [`Self::advance`].
    pub q: Vec<f64>,
    pub block: Option<BlockId>,
    pub attachments: Vec<Attachment>,
    /// Rows of this step, 3 per attachment (`None`: not needed).
    rows: Vec<Option<RowId>>,
    /// Attachment forces on the nodes from the last step, N.
    reactions: Vec<Vector3<f64>>,
    /// One row's coefficients on the block (`nfree`, scratch, zero between uses).
    coefs: Vec<f64>,
    /// The three rows of a proxy on the free coordinates (`3 nfree`, zero between
    /// calls): `proxy_jacobian` takes `&self`.
    jacobian: Mutex<Vec<f64>>,
}

impl ImplicitBlock {
    /// The block of a mesh with `ndof` coordinates numbered by `map`, `n_elements`
    /// elements of `el_ndof` coordinates each; `global(e, a)` is the global coordinate
    /// of local coordinate `a` of element `e`, `mass(e)` the element's consistent mass
    /// matrix. Errors: no element, every coordinate supported.
    pub fn new<M>(
        name: String,
        map: DofMap,
        n_elements: usize,
        el_ndof: usize,
        global: impl Fn(usize, usize) -> usize,
        mass: impl Fn(usize) -> M,
    ) -> Result<Self>
    where
        M: std::ops::Index<(usize, usize), Output = f64>,
    {
        if n_elements == 0 {
            return Err(FeaError::invalid("mesh.elements", 0, "needs an element"));
        }
        let n = map.nfree();
        if n == 0 {
            return Err(FeaError::invalid(
                "mesh",
                "all coordinates supported",
                "needs a free coordinate",
            ));
        }
        let ndof = map.ndof();
        let free_global: Vec<usize> = (0..ndof).filter(|&g| map.free_index(g).is_some()).collect();
        let pair = |e: usize, a: usize, b: usize| -> Option<(usize, usize)> {
            let i = map.free_index(global(e, a))?;
            let j = map.free_index(global(e, b))?;
            (i <= j).then_some((i, j))
        };
        // The diagonal is always present (the mass is positive definite).
        let mut trip: Vec<Triplet<usize, usize, f64>> =
            (0..n).map(|f| Triplet::new(f, f, 0.0)).collect();
        for e in 0..n_elements {
            for a in 0..el_ndof {
                for b in 0..el_ndof {
                    if let Some((i, j)) = pair(e, a, b) {
                        trip.push(Triplet::new(i, j, 0.0));
                    }
                }
            }
        }
        let pattern = SparseColMat::try_new_from_triplets(n, n, &trip)
            .map_err(|e| FeaError::Assembly(format!("{e:?}")))?;
        let (cp, ri) = (
            pattern.symbolic().col_ptr().to_vec(),
            pattern.symbolic().row_idx().to_vec(),
        );
        // Row indices are sorted within a column: binary search.
        let find = |i: usize, j: usize| -> usize {
            cp[j]
                + ri[cp[j]..cp[j + 1]]
                    .binary_search(&i)
                    .expect("entry in the pattern")
        };
        let mut scatter = vec![NONE; n_elements * el_ndof * el_ndof];
        let mut mass_matrix = pattern.clone();
        let mvals = mass_matrix.val_mut();
        mvals.fill(0.0);
        for e in 0..n_elements {
            let me = mass(e);
            for a in 0..el_ndof {
                for b in 0..el_ndof {
                    if let Some((i, j)) = pair(e, a, b) {
                        let idx = find(i, j);
                        scatter[(e * el_ndof + a) * el_ndof + b] = idx;
                        mvals[idx] += me[(a, b)];
                    }
                }
            }
        }
        let op = Arc::new(SparseSpd::new(pattern)?);
        let nnz = op.nnz();
        Ok(Self {
            label: format!("FEA item \"{name}\""),
            map,
            free_global,
            velocity: vec![0.0; ndof],
            op,
            mass: mass_matrix,
            el_ndof,
            scatter,
            h_values: vec![0.0; nnz],
            force: vec![0.0; ndof],
            q: vec![0.0; ndof],
            block: None,
            attachments: Vec::new(),
            rows: Vec::new(),
            reactions: Vec::new(),
            coefs: vec![0.0; n],
            jacobian: Mutex::new(vec![0.0; 3 * n]),
        })
    }

    /// Start assembling `H` for a step: `H = M`.
    pub fn begin_assembly(&mut self) {
        self.h_values.copy_from_slice(self.mass.val());
    }

    /// `H += c m` for the element matrix `m` of element `e` (its upper triangle on the
    /// free coordinates: `m` must be symmetric).
    pub fn add_element_matrix<M>(&mut self, e: usize, m: &M, c: f64)
    where
        M: std::ops::Index<(usize, usize), Output = f64>,
    {
        let n = self.el_ndof;
        for a in 0..n {
            for b in 0..n {
                let idx = self.scatter[(e * n + a) * n + b];
                if idx != NONE {
                    self.h_values[idx] += c * m[(a, b)];
                }
            }
        }
    }

    /// Check `f(q)` (`stride`: coordinates per node, for the message) and factorize `H`.
    pub fn finish_assembly(&mut self, ctx: &StepContext, stride: usize) -> CoreResult<()> {
        if let Some(i) = self.force.iter().position(|x| !x.is_finite()) {
            return Err(ChronoError::NonFinite {
                item: self.label.clone(),
                step: ctx.step,
                time: ctx.time,
                what: format!("internal force (coordinate {i} of node {})", i / stride),
            });
        }
        self.op
            .refactor(&self.h_values)
            .map_err(|e| ChronoError::Diverged {
                item: self.label.clone(),
                step: ctx.step,
                time: ctx.time,
                what: format!(
                    "iteration matrix M + h R + h^2 K (h = {} s): {e}; reduce the step size",
                    ctx.h
                ),
            })
    }

    /// Register the block (`H` as its coupled mass operator).
    pub fn add_variables(&mut self, vars: &mut Variables) {
        self.block = Some(vars.add(MassOperator::Coupled(self.op.clone())));
    }

    /// `M v` on the free coordinates (`out` of length `nfree`).
    fn mass_times_velocity(&self, out: &mut [f64]) {
        let v: Vec<f64> = self.free_global.iter().map(|&g| self.velocity[g]).collect();
        symmetric_upper_mul(self.mass.as_ref(), &v, out);
    }

    /// `k = M v + h f(q)` on the free coordinates.
    pub fn load_momentum(&self, ctx: &StepContext, vars: &Variables, k: &mut [f64]) {
        let Some(blk) = self.block else { return };
        let kb = &mut k[vars.range(blk)];
        let m = self.mass.as_ref();
        let s = m.symbolic();
        let (cp, ri, val) = (s.col_ptr(), s.row_idx(), m.val());
        let v = |f: usize| self.velocity[self.free_global[f]];
        for j in 0..kb.len() {
            for idx in cp[j]..cp[j + 1] {
                let (i, a) = (ri[idx], val[idx]);
                kb[i] += a * v(j);
                if i != j {
                    kb[j] += a * v(i);
                }
            }
        }
        for (f, &g) in self.free_global.iter().enumerate() {
            kb[f] += ctx.h * self.force[g];
        }
    }

    /// Kinetic energy `v' M v / 2` (consistent mass), J.
    pub fn kinetic_energy(&self) -> f64 {
        let mut mv = vec![0.0; self.free_global.len()];
        self.mass_times_velocity(&mut mv);
        0.5 * self
            .free_global
            .iter()
            .zip(&mv)
            .map(|(&g, m)| self.velocity[g] * m)
            .sum::<f64>()
    }

    /// `sum_ab M_ab v_b` summed per axis over the coordinates `g` with
    /// `position(g) = Some(axis)`: the linear momentum when those are the coordinates
    /// that carry translations (kg m/s).
    pub fn momentum(&self, axis_of: impl Fn(usize) -> Option<usize>) -> Vector3<f64> {
        let mut mv = vec![0.0; self.free_global.len()];
        self.mass_times_velocity(&mut mv);
        let mut p = Vector3::zeros();
        for (f, &g) in self.free_global.iter().enumerate() {
            if let Some(a) = axis_of(g) {
                p[a] += mv[f];
            }
        }
        p
    }

    /// Angular momentum about the origin `sum_n q_n x (M v)_n` over the 3-vectors of
    /// coordinates `[3k, 3k + 3)` (positions and directors alike: each rotates as a
    /// vector under a rigid rotation, so each carries `q x p`), kg m^2/s. Supported
    /// coordinates carry no momentum.
    pub fn angular_momentum(&self) -> Vector3<f64> {
        let mut mv = vec![0.0; self.free_global.len()];
        self.mass_times_velocity(&mut mv);
        let mut p = vec![0.0; self.q.len()];
        for (f, &g) in self.free_global.iter().enumerate() {
            p[g] = mv[f];
        }
        let mut l = Vector3::zeros();
        for (q, p) in self.q.chunks_exact(3).zip(p.chunks_exact(3)) {
            l += Vector3::new(q[0], q[1], q[2]).cross(&Vector3::new(p[0], p[1], p[2]));
        }
        l
    }

    /// Set the velocity of coordinates `first .. first + values.len()` (`what` names
    /// them in errors); a non-zero value on a supported coordinate is an error.
    pub fn set_velocity(&mut self, first: usize, values: &[f64], what: &str) -> Result<()> {
        for (k, &x) in values.iter().enumerate() {
            if !x.is_finite() {
                return Err(FeaError::invalid(
                    format!("{what}[{k}]"),
                    x,
                    "must be finite",
                ));
            }
            if x != 0.0 && self.map.free_index(first + k).is_none() {
                return Err(FeaError::invalid(
                    format!("{what}[{k}]"),
                    x,
                    "a supported coordinate cannot move",
                ));
            }
        }
        self.velocity[first..first + values.len()].copy_from_slice(values);
        Ok(())
    }

    /// Store an attachment (the node must exist: checked by the caller); returns its
    /// index. Errors: a non-finite point.
    pub fn attach(&mut self, node: NodeId, target: AttachTarget) -> Result<usize> {
        match &target {
            AttachTarget::Point(p) => finite3("attachment.point", p)?,
            AttachTarget::Body { local, .. } => finite3("attachment.local", local)?,
        }
        self.attachments.push(Attachment { node, target });
        self.reactions.push(Vector3::zeros());
        Ok(self.attachments.len() - 1)
    }

    /// The force of attachment `i` on its node during the last step (`gamma / h`), N.
    pub fn reaction(&self, i: usize) -> Option<Vector3<f64>> {
        self.reactions.get(i).copied()
    }

    /// The attachment rows of this step (see [`crate::attach_rows`]); `position(n)` is
    /// node `n`'s position, its coordinates `stride n .. stride n + 3`.
    pub fn attachment_rows(
        &mut self,
        ctx: &StepContext,
        bodies: &chrono_core::Bodies,
        rows: &mut ConstraintRows,
        stride: usize,
        position: impl Fn(usize) -> CoreResult<Vector3<f64>>,
    ) -> CoreResult<()> {
        self.rows.clear();
        let Some(blk) = self.block else {
            return Ok(());
        };
        let actx = AttachContext {
            block: blk,
            bodies,
            h: ctx.h,
            label: &self.label,
        };
        let map = &self.map;
        self.coefs.fill(0.0);
        push_attachment_rows(
            &self.attachments,
            position,
            |n, d| map.free_index(stride * n + d),
            &actx,
            &mut self.coefs,
            rows,
            &mut self.rows,
        )
    }

    /// The Jacobian of a point `sum_k s_k x_k` of the mesh along `dirs`: `s_k d` on the
    /// free coordinates of each 3-block `x_k` (`weights`: the first global coordinate of
    /// the block and its weight `s_k`). Nothing if no coordinate is free.
    pub fn point_jacobian(
        &self,
        weights: &[(usize, f64)],
        dirs: &[Vector3<f64>; 3],
        entry: &mut dyn FnMut(BlockId, [&[f64]; 3]),
    ) {
        let Some(blk) = self.block else { return };
        let n = self.free_global.len();
        // A poisoned lock only means a panic elsewhere; the buffer is re-zeroed below.
        let mut buf = self.jacobian.lock().unwrap_or_else(|e| e.into_inner());
        let mut touched = false;
        for &(g, s) in weights {
            for c in 0..3 {
                if let Some(f) = self.map.free_index(g + c)
                    && s != 0.0
                {
                    for (k, d) in dirs.iter().enumerate() {
                        buf[k * n + f] += s * d[c];
                    }
                    touched = true;
                }
            }
        }
        if touched {
            let (j0, rest) = buf.split_at(n);
            let (j1, j2) = rest.split_at(n);
            entry(blk, [j0, j1, j2]);
            for &(g, _) in weights {
                for c in 0..3 {
                    if let Some(f) = self.map.free_index(g + c) {
                        for k in 0..3 {
                            buf[k * n + f] = 0.0;
                        }
                    }
                }
            }
        }
    }

    /// `v+` from the solution, `q+ = q + h v+` (into [`Self::q`]), the attachment forces
    /// `gamma / h`. `stride`: coordinates per node (for the message). The caller copies
    /// `q` into its mesh.
    pub fn advance(
        &mut self,
        ctx: &StepContext,
        vars: &Variables,
        v: &[f64],
        problem: &CcpProblem,
        gamma: &[f64],
        stride: usize,
    ) -> CoreResult<bool> {
        let Some(blk) = self.block else {
            return Ok(false);
        };
        let vb = &v[vars.range(blk)];
        for (f, &g) in self.free_global.iter().enumerate() {
            self.velocity[g] = vb[f];
        }
        for (g, qg) in self.q.iter_mut().enumerate() {
            *qg += ctx.h * self.velocity[g];
        }
        if let Some(i) = self.q.iter().position(|x| !x.is_finite()) {
            return Err(ChronoError::NonFinite {
                item: self.label.clone(),
                step: ctx.step,
                time: ctx.time,
                what: format!("coordinate {i} of node {}", i / stride),
            });
        }
        for (ai, r) in self.reactions.iter_mut().enumerate() {
            *r = Vector3::zeros();
            for d in 0..3 {
                if let Some(Some(id)) = self.rows.get(3 * ai + d) {
                    r[d] = gamma[problem.row_index(*id)] / ctx.h;
                }
            }
        }
        Ok(true)
    }
}

/// A chrono-fea error as a chrono-core one (inside a step): the cause is kept as the
/// source, so the message still names the real field (`material.young`, `coordinates[3]`).
pub(crate) fn core_error(e: FeaError) -> ChronoError {
    ChronoError::domain("chrono-fea", e)
}
