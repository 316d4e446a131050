//! A mesh of ANCF cable elements: nodes, elements, supports, loads and the global
//! (sparse) assembly of forces, tangent stiffness and mass.
//!
//! Global coordinates: node `n` owns `q[6 n .. 6 n + 6] = [r, r_x]`. Supports remove
//! coordinates: a fixed position removes the 3 position coordinates of the node, a fixed
//! slope the 3 slope coordinates (both: a clamp). The remaining *free* coordinates are
//! numbered by a [`DofMap`]; the matrices the solvers factorize live on them.

use faer::sparse::{SparseColMat, Triplet};
use nalgebra::Vector3;

use crate::element::{AncfCable, CableQuadrature, ElementVector};
use crate::error::{FeaError, Result, finite3};
use crate::material::BeamMaterial;
use crate::node::{GradientNode, NodeId};

/// The sparse matrix type of the assembly (faer, compressed columns).
pub type SparseMatrix = SparseColMat<usize, f64>;

/// Tolerance on the unit length of a reference slope and on its alignment with the chord.
const REFERENCE_TOLERANCE: f64 = 1e-9;

/// Numbering of the free coordinates: `free[g]` is the free index of global coordinate
/// `g`, or `None` when a support holds it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DofMap {
    free: Vec<Option<usize>>,
    nfree: usize,
}

impl DofMap {
    /// The numbering of the coordinates whose `fixed` flag is false, in order.
    pub fn from_fixed(fixed: impl IntoIterator<Item = bool>) -> Self {
        let mut nfree = 0;
        let free = fixed
            .into_iter()
            .map(|f| {
                (!f).then(|| {
                    nfree += 1;
                    nfree - 1
                })
            })
            .collect();
        Self { free, nfree }
    }

    /// Free index of global coordinate `g`.
    pub fn free_index(&self, g: usize) -> Option<usize> {
        self.free[g]
    }

    /// Number of free coordinates.
    pub fn nfree(&self) -> usize {
        self.nfree
    }

    /// Number of global coordinates.
    pub fn ndof(&self) -> usize {
        self.free.len()
    }

    /// The free entries of a global vector.
    pub fn restrict(&self, global: &[f64]) -> Vec<f64> {
        let mut out = vec![0.0; self.nfree];
        for (g, f) in self.free.iter().enumerate() {
            if let Some(i) = f {
                out[*i] = global[g];
            }
        }
        out
    }
}

/// A mesh of gradient-deficient ANCF cable elements (see [`AncfCable`]).
#[derive(Debug, Clone, Default)]
pub struct CableMesh {
    nodes: Vec<GradientNode>,
    elements: Vec<AncfCable>,
    gravity: Vector3<f64>,
    /// Applied generalized load on the coordinates (6 per node; empty: none).
    coordinate_load: Vec<f64>,
}

impl CableMesh {
    /// An empty mesh without gravity.
    pub fn new() -> Self {
        Self::default()
    }

    /// A straight beam from `start` to `end` (m) of `n_elements` equal elements, all with
    /// `material`; nodes are numbered from `start`, slopes are the unit direction.
    pub fn straight(
        start: Vector3<f64>,
        end: Vector3<f64>,
        n_elements: usize,
        material: BeamMaterial,
        quadrature: CableQuadrature,
    ) -> Result<Self> {
        if n_elements == 0 {
            return Err(FeaError::invalid("n_elements", 0, "must be >= 1"));
        }
        finite3("start", &start)?;
        finite3("end", &end)?;
        let chord = end - start;
        let length = chord.norm();
        if length <= 0.0 {
            return Err(FeaError::invalid(
                "end",
                format!("{end:?}"),
                "must differ from `start`",
            ));
        }
        let dir = chord / length;
        let mut mesh = Self::new();
        for i in 0..=n_elements {
            mesh.add_node(start + chord * (i as f64 / n_elements as f64), dir)?;
        }
        for i in 0..n_elements {
            mesh.add_cable(NodeId(i), NodeId(i + 1), material, quadrature)?;
        }
        Ok(mesh)
    }

    /// Add a node at `position` (m) with unit reference slope `slope`; the node starts in
    /// its reference configuration, free and unloaded.
    pub fn add_node(&mut self, position: Vector3<f64>, slope: Vector3<f64>) -> Result<NodeId> {
        finite3("node.position", &position)?;
        finite3("node.slope", &slope)?;
        if (slope.norm() - 1.0).abs() > REFERENCE_TOLERANCE {
            return Err(FeaError::invalid(
                "node.slope",
                format!("{slope:?} (norm {})", slope.norm()),
                "the reference slope must be a unit vector (x is the reference arc length)",
            ));
        }
        self.nodes.push(GradientNode::new(position, slope));
        Ok(NodeId(self.nodes.len() - 1))
    }

    /// Add a cable element between nodes `a` and `b`. The reference configuration must be
    /// straight: both reference slopes along the chord `b - a` (curved reference shapes
    /// need a reference curvature in the element, not implemented yet).
    pub fn add_cable(
        &mut self,
        a: NodeId,
        b: NodeId,
        material: BeamMaterial,
        quadrature: CableQuadrature,
    ) -> Result<usize> {
        let index = self.elements.len();
        for n in [a, b] {
            if n.0 >= self.nodes.len() {
                return Err(FeaError::invalid(
                    format!("element {index}.node"),
                    n.0,
                    format!("no such node (the mesh has {})", self.nodes.len()),
                ));
            }
        }
        if a == b {
            return Err(FeaError::invalid(
                format!("element {index}.nodes"),
                a.0,
                "the two nodes must differ",
            ));
        }
        let (na, nb) = (&self.nodes[a.0], &self.nodes[b.0]);
        let chord = nb.reference_position - na.reference_position;
        let length = chord.norm();
        if length <= 0.0 {
            return Err(FeaError::invalid(
                format!("element {index}.length"),
                length,
                "the two nodes are at the same reference position",
            ));
        }
        let dir = chord / length;
        for (n, node) in [(a, na), (b, nb)] {
            if (node.reference_slope - dir).norm() > 1e3 * REFERENCE_TOLERANCE {
                return Err(FeaError::invalid(
                    format!("element {index}: reference slope of node {}", n.0),
                    format!("{:?}", node.reference_slope),
                    format!(
                        "must be the unit chord direction {dir:?} (only straight reference configurations are supported)"
                    ),
                ));
            }
        }
        self.elements
            .push(AncfCable::new([a.0, b.0], length, material, quadrature)?);
        Ok(index)
    }

    fn node_mut(&mut self, n: NodeId) -> Result<&mut GradientNode> {
        let count = self.nodes.len();
        self.nodes.get_mut(n.0).ok_or_else(|| {
            FeaError::invalid("node", n.0, format!("no such node (the mesh has {count})"))
        })
    }

    /// The node `n`.
    pub fn node(&self, n: NodeId) -> Result<&GradientNode> {
        self.nodes.get(n.0).ok_or_else(|| {
            FeaError::invalid(
                "node",
                n.0,
                format!("no such node (the mesh has {})", self.nodes.len()),
            )
        })
    }

    /// All nodes.
    pub fn nodes(&self) -> &[GradientNode] {
        &self.nodes
    }

    /// All elements.
    pub fn elements(&self) -> &[AncfCable] {
        &self.elements
    }

    /// Hold the position of node `n` fixed.
    pub fn fix_position(&mut self, n: NodeId) -> Result<()> {
        self.node_mut(n)?.fixed[..3].fill(true);
        Ok(())
    }

    /// Hold the whole slope `r_x` of node `n` fixed: its direction *and* its length, so
    /// the axial strain at the node is held at its current value too.
    pub fn fix_slope(&mut self, n: NodeId) -> Result<()> {
        self.node_mut(n)?.fixed[3..].fill(true);
        Ok(())
    }

    /// Hold the direction of the slope of node `n` (the rotation of the section) and leave
    /// its length (the axial stretch) free: the two slope components normal to the
    /// reference slope are fixed. Needs a reference slope along a coordinate axis (the
    /// supports remove coordinates; a general direction, or one that turns with a rigid
    /// body, needs constraint rows: [`CableItem::attach_slope`](crate::CableItem::attach_slope)).
    pub fn fix_slope_direction(&mut self, n: NodeId) -> Result<()> {
        let node = self.node_mut(n)?;
        let t = node.reference_slope;
        let Some(axis) = (0..3).find(|&i| (t[i].abs() - 1.0).abs() < REFERENCE_TOLERANCE) else {
            return Err(FeaError::invalid(
                format!("node {}.reference_slope", n.0),
                format!("{t:?}"),
                "a slope-direction support needs a slope along a coordinate axis",
            ));
        };
        for i in 0..3 {
            if i != axis {
                node.fixed[3 + i] = true;
            }
        }
        Ok(())
    }

    /// Clamp node `n`: position and slope direction fixed (see
    /// [`fix_slope_direction`](Self::fix_slope_direction)); the stretch at the clamp stays
    /// free, as in a real clamp, so a uniform pull stretches the beam uniformly.
    pub fn clamp(&mut self, n: NodeId) -> Result<()> {
        self.fix_position(n)?;
        self.fix_slope_direction(n)
    }

    /// Set the applied (dead) force on node `n`, N.
    pub fn set_force(&mut self, n: NodeId, force: Vector3<f64>) -> Result<()> {
        finite3("node.force", &force)?;
        self.node_mut(n)?.force = force;
        Ok(())
    }

    /// Set the gravity acceleration, m/s^2 (a distributed load `rho A g`).
    pub fn set_gravity(&mut self, gravity: Vector3<f64>) -> Result<()> {
        finite3("gravity", &gravity)?;
        self.gravity = gravity;
        Ok(())
    }

    /// The gravity acceleration, m/s^2.
    pub fn gravity(&self) -> Vector3<f64> {
        self.gravity
    }

    /// Set an applied generalized load on the nodal coordinates, a dead load added to the
    /// nodal forces: `load[6 n .. 6 n + 3]` on node `n`'s position (N) and
    /// `load[6 n + 3 .. 6 n + 6]` on its slope (N m). A distributed force `f(x)` along the
    /// centre line enters as `Q_k = ∫ S_k f dx` (`S_k` the element's shape functions), so
    /// `Q . q_dot` is the power of `f` (e.g. fluid forces interpolated by chrono-fsi).
    /// Errors: a length other than [`ndof`](Self::ndof) or a value that is not finite.
    /// An empty slice removes it.
    pub fn set_coordinate_load(&mut self, load: &[f64]) -> Result<()> {
        if load.is_empty() {
            self.coordinate_load.clear();
            return Ok(());
        }
        crate::error::check_coordinates(load, self.ndof(), 6).map_err(|_| {
            FeaError::invalid(
                "coordinate_load",
                format!("{} values", load.len()),
                format!("must be {} finite values (6 per node)", self.ndof()),
            )
        })?;
        self.coordinate_load.clear();
        self.coordinate_load.extend_from_slice(load);
        Ok(())
    }

    /// The applied generalized load on the coordinates (empty: none;
    /// [`set_coordinate_load`](Self::set_coordinate_load)).
    pub fn coordinate_load(&self) -> &[f64] {
        &self.coordinate_load
    }

    /// Number of global coordinates (6 per node).
    pub fn ndof(&self) -> usize {
        GradientNode::NDOF * self.nodes.len()
    }

    /// Total mass `sum rho A L`, kg.
    pub fn total_mass(&self) -> f64 {
        self.elements
            .iter()
            .map(|e| e.material().mass_per_length() * e.length())
            .sum()
    }

    /// The numbering of the free coordinates.
    pub fn dof_map(&self) -> DofMap {
        DofMap::from_fixed(
            self.nodes
                .iter()
                .flat_map(|n| (0..GradientNode::NDOF).map(|k| n.is_fixed(k))),
        )
    }

    /// The global coordinate vector `q` of the current configuration.
    pub fn coordinates(&self) -> Vec<f64> {
        let mut q = Vec::with_capacity(self.ndof());
        for n in &self.nodes {
            q.extend_from_slice(n.position.as_slice());
            q.extend_from_slice(n.slope.as_slice());
        }
        q
    }

    /// Set the current configuration from a global coordinate vector (length
    /// [`ndof`](Self::ndof), finite).
    pub fn set_coordinates(&mut self, q: &[f64]) -> Result<()> {
        crate::error::check_coordinates(q, self.ndof(), 6)?;
        for (n, node) in self.nodes.iter_mut().enumerate() {
            node.position = Vector3::new(q[6 * n], q[6 * n + 1], q[6 * n + 2]);
            node.slope = Vector3::new(q[6 * n + 3], q[6 * n + 4], q[6 * n + 5]);
        }
        Ok(())
    }

    /// The 12 element coordinates of element `el` taken from the global vector `q`.
    pub fn element_coordinates(&self, el: &AncfCable, q: &[f64]) -> ElementVector {
        let mut e = ElementVector::zeros();
        for (k, &n) in el.nodes.iter().enumerate() {
            for i in 0..6 {
                e[6 * k + i] = q[6 * n + i];
            }
        }
        e
    }

    /// Global coordinate index of element-local coordinate `i` (0..12) of `el`.
    fn global_index(el: &AncfCable, i: usize) -> usize {
        6 * el.nodes[i / 6] + i % 6
    }

    /// The applied load at load factor `lambda`: `lambda (F_nodal + Q_coord + Q_gravity)`
    /// (`Q_coord`: [`set_coordinate_load`](Self::set_coordinate_load)), a global
    /// vector (N for the position rows, N m for the slope rows).
    pub fn external_force(&self, lambda: f64) -> Vec<f64> {
        let mut f = vec![0.0; self.ndof()];
        for (n, node) in self.nodes.iter().enumerate() {
            for i in 0..3 {
                f[6 * n + i] += lambda * node.force[i];
            }
        }
        for (fi, li) in f.iter_mut().zip(&self.coordinate_load) {
            *fi += lambda * li;
        }
        if self.gravity != Vector3::zeros() {
            for el in &self.elements {
                let qg = el.gravity_force(&self.gravity);
                for i in 0..12 {
                    f[Self::global_index(el, i)] += lambda * qg[i];
                }
            }
        }
        f
    }

    /// The global internal force `Q(q) = dU/dq` and, if `tangent`, the tangent stiffness
    /// on the free coordinates of `map` as a sparse matrix (duplicates summed).
    pub fn internal_force(
        &self,
        q: &[f64],
        map: &DofMap,
        tangent: bool,
    ) -> Result<(Vec<f64>, Option<SparseMatrix>)> {
        let mut f = vec![0.0; self.ndof()];
        let mut trip = Vec::new();
        for el in &self.elements {
            let e = self.element_coordinates(el, q);
            let (qe, ke) = el.force_and_tangent(&e, tangent);
            for i in 0..12 {
                f[Self::global_index(el, i)] += qe[i];
            }
            if tangent {
                scatter_element_matrix(&el.nodes, 6, &ke, map, &mut trip);
            }
        }
        let k = if tangent {
            Some(sparse(map.nfree(), &trip)?)
        } else {
            None
        };
        Ok((f, k))
    }

    /// The consistent mass matrix on the free coordinates of `map`, kg.
    pub fn mass_matrix(&self, map: &DofMap) -> Result<SparseColMat<usize, f64>> {
        let mut trip = Vec::new();
        for el in &self.elements {
            scatter_element_matrix(&el.nodes, 6, &el.mass_matrix(), map, &mut trip);
        }
        sparse(map.nfree(), &trip)
    }

    /// Strain energy of the current configuration, J.
    pub fn strain_energy(&self) -> f64 {
        let q = self.coordinates();
        self.elements
            .iter()
            .map(|el| el.strain_energy(&self.element_coordinates(el, &q)))
            .sum()
    }
}

/// Add an element matrix to the triplets of the free coordinates. The element's local
/// coordinate `i` is coordinate `i % per_node` of its node `nodes[i / per_node]`, i.e. the
/// global coordinate `per_node * nodes[i / per_node] + i % per_node` (every mesh here
/// numbers a node's coordinates contiguously). Rows or columns of fixed coordinates are
/// dropped.
pub(crate) fn scatter_element_matrix<M>(
    nodes: &[usize],
    per_node: usize,
    m: &M,
    map: &DofMap,
    trip: &mut Vec<Triplet<usize, usize, f64>>,
) where
    M: std::ops::Index<(usize, usize), Output = f64>,
{
    let n = nodes.len() * per_node;
    let global = |i: usize| per_node * nodes[i / per_node] + i % per_node;
    for i in 0..n {
        let Some(fi) = map.free_index(global(i)) else {
            continue;
        };
        for j in 0..n {
            if let Some(fj) = map.free_index(global(j)) {
                trip.push(Triplet::new(fi, fj, m[(i, j)]));
            }
        }
    }
}

/// A square sparse matrix of size `n` from triplets (duplicates summed).
pub(crate) fn sparse(
    n: usize,
    trip: &[Triplet<usize, usize, f64>],
) -> Result<SparseColMat<usize, f64>> {
    SparseColMat::try_new_from_triplets(n, n, trip)
        .map_err(|e| FeaError::Assembly(format!("{e:?}")))
}

crate::statics::static_model_via_inherent!(CableMesh {
    /// `max_e E A`, N.
    fn force_scale(&self) -> f64 {
        self.elements
            .iter()
            .map(|e| e.material().axial_stiffness())
            .fold(0.0, f64::max)
    }
});
