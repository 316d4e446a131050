//! A mesh of fully parameterized ANCF beam elements ([`AncfBeam`]): nodes with a
//! position and three gradients, elements, supports, nodal loads, gravity, and the global
//! (sparse) assembly of forces, tangent stiffness and mass.
//!
//! Global coordinates: node `n` owns `q[12 n .. 12 n + 12] = [r, r_x, r_y, r_z]`.
//! Supports hold coordinates at their current values: [`BeamMesh::clamp`] (all 12),
//! [`BeamMesh::fix_position`] (a spherical joint), [`BeamMesh::fix_coordinate`]. Loads are dead: nodal forces, couples
//! ([`BeamMesh::set_torque`]) and gravity. The mesh implements [`StaticModel`](crate::statics::StaticModel), so
//! [`solve_static`](crate::statics::solve_static) (Newton with load stepping) solves it.
//!
//! Generators: [`BeamMesh::straight`] and [`BeamMesh::arc`] (a circular arc whose
//! reference configuration is the stress-free curved shape).

use nalgebra::Vector3;

use crate::element::{AncfBeam, BeamQuadrature, BeamVector};
use crate::error::{FeaError, Result, finite3, positive};
use crate::material::BeamSection;
use crate::mesh::{DofMap, SparseMatrix, scatter_element_matrix, sparse};
use crate::node::{BeamNode, NodeId};

/// Tolerance on the unit length and orthogonality of a node's reference gradients.
const FRAME_TOLERANCE: f64 = 1e-9;

/// A mesh of fully parameterized ANCF beam elements (see the module docs).
#[derive(Debug, Clone, Default)]
pub struct BeamMesh {
    nodes: Vec<BeamNode>,
    elements: Vec<AncfBeam>,
    gravity: Vector3<f64>,
}

impl BeamMesh {
    /// An empty mesh without gravity.
    pub fn new() -> Self {
        Self::default()
    }

    /// A straight beam from `start` to `end` (m) of `n_elements` equal elements; the
    /// section's `y` axis (`r_y`) is `y_axis` made normal to the beam axis, `r_z = r_x x r_y`.
    pub fn straight(
        start: Vector3<f64>,
        end: Vector3<f64>,
        n_elements: usize,
        y_axis: Vector3<f64>,
        section: BeamSection,
    ) -> Result<Self> {
        if n_elements == 0 {
            return Err(FeaError::invalid("n_elements", 0, "must be >= 1"));
        }
        finite3("start", &start)?;
        finite3("end", &end)?;
        finite3("y_axis", &y_axis)?;
        let chord = end - start;
        let length = chord.norm();
        if length <= 0.0 {
            return Err(FeaError::invalid(
                "end",
                format!("{end:?}"),
                "must differ from `start`",
            ));
        }
        let t = chord / length;
        let y = y_axis - t * t.dot(&y_axis);
        if y.norm() <= 1e-6 * y_axis.norm() || y.norm() == 0.0 {
            return Err(FeaError::invalid(
                "y_axis",
                format!("{y_axis:?}"),
                "must not be parallel to the beam axis",
            ));
        }
        let y = y.normalize();
        let frame = [t, y, t.cross(&y)];
        let mut mesh = Self::new();
        for i in 0..=n_elements {
            mesh.add_node(start + chord * (i as f64 / n_elements as f64), frame)?;
        }
        for i in 0..n_elements {
            mesh.add_element(NodeId(i), NodeId(i + 1), section)?;
        }
        Ok(mesh)
    }

    /// A circular arc of `radius` (m) through `angle` (rad, in (0, 2 pi)) with
    /// `n_elements` equal elements. It starts at `origin` with the unit tangent `tangent`
    /// and bends towards `toward` (made normal to `tangent`); the centre is at
    /// `origin + radius n` (`n` the unit normal towards `toward`). Node `i` at
    /// `phi = angle i / n`: position `origin + R sin(phi) t + R (1 - cos phi) n`,
    /// gradients `r_x = cos(phi) t + sin(phi) n` (the tangent), `r_y = -sin(phi) t +
    /// cos(phi) n` (towards the centre), `r_z = t x n` (normal to the plane). The arc is
    /// the stress-free reference of its elements.
    pub fn arc(
        origin: Vector3<f64>,
        tangent: Vector3<f64>,
        toward: Vector3<f64>,
        radius: f64,
        angle: f64,
        n_elements: usize,
        section: BeamSection,
    ) -> Result<Self> {
        if n_elements == 0 {
            return Err(FeaError::invalid("n_elements", 0, "must be >= 1"));
        }
        finite3("origin", &origin)?;
        finite3("tangent", &tangent)?;
        finite3("toward", &toward)?;
        let r = positive("radius", radius)?;
        if !(angle.is_finite() && angle > 0.0 && angle < std::f64::consts::TAU) {
            return Err(FeaError::invalid(
                "angle",
                angle,
                "must be in (0, 2 pi) rad",
            ));
        }
        if tangent.norm() == 0.0 {
            return Err(FeaError::invalid(
                "tangent",
                "[0, 0, 0]",
                "must be non-zero",
            ));
        }
        let t = tangent.normalize();
        let n = toward - t * t.dot(&toward);
        if n.norm() <= 1e-6 * toward.norm() || n.norm() == 0.0 {
            return Err(FeaError::invalid(
                "toward",
                format!("{toward:?}"),
                "must not be parallel to `tangent`",
            ));
        }
        let n = n.normalize();
        let z = t.cross(&n);
        let mut mesh = Self::new();
        for i in 0..=n_elements {
            let phi = angle * i as f64 / n_elements as f64;
            let (s, c) = phi.sin_cos();
            mesh.add_node(
                origin + r * s * t + r * (1.0 - c) * n,
                [c * t + s * n, -s * t + c * n, z],
            )?;
        }
        for i in 0..n_elements {
            mesh.add_element(NodeId(i), NodeId(i + 1), section)?;
        }
        Ok(mesh)
    }

    /// Add a node at `position` (m) with the reference gradients `[r_x, r_y, r_z]`: an
    /// orthonormal frame (unit tangent, unit section axes), within `1e-9`.
    pub fn add_node(
        &mut self,
        position: Vector3<f64>,
        gradients: [Vector3<f64>; 3],
    ) -> Result<NodeId> {
        finite3("node.position", &position)?;
        for (k, g) in gradients.iter().enumerate() {
            finite3(&format!("node.gradient[{k}]"), g)?;
            if (g.norm() - 1.0).abs() > FRAME_TOLERANCE {
                return Err(FeaError::invalid(
                    format!("node.gradient[{k}]"),
                    format!("{g:?} (norm {})", g.norm()),
                    "the reference gradients must be unit vectors",
                ));
            }
        }
        for (i, j) in [(0, 1), (0, 2), (1, 2)] {
            let d = gradients[i].dot(&gradients[j]);
            if d.abs() > FRAME_TOLERANCE {
                return Err(FeaError::invalid(
                    format!("node.gradient[{i}] . node.gradient[{j}]"),
                    d,
                    "the reference gradients must be orthogonal",
                ));
            }
        }
        self.nodes.push(BeamNode::new(position, gradients));
        Ok(NodeId(self.nodes.len() - 1))
    }

    /// Add an element between nodes `a` and `b` with the default quadrature.
    pub fn add_element(&mut self, a: NodeId, b: NodeId, section: BeamSection) -> Result<usize> {
        self.add_element_with(a, b, section, BeamQuadrature::default())
    }

    /// Add an element between nodes `a` and `b`; its reference configuration is that of
    /// the nodes (stress free), its parameter length from
    /// [`AncfBeam::reference_length`]. Errors name the element and the field.
    pub fn add_element_with(
        &mut self,
        a: NodeId,
        b: NodeId,
        section: BeamSection,
        quadrature: BeamQuadrature,
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
        let reference = Self::reference_vectors(&self.nodes[a.0], &self.nodes[b.0]);
        let length = AncfBeam::reference_length(&reference);
        let el = AncfBeam::new([a.0, b.0], &reference, length, section, quadrature).map_err(
            |e| match e {
                FeaError::InvalidParameter {
                    field,
                    value,
                    reason,
                } => FeaError::InvalidParameter {
                    field: format!("element {index}: {field}"),
                    value,
                    reason,
                },
                other => other,
            },
        )?;
        self.elements.push(el);
        Ok(index)
    }

    fn reference_vectors(a: &BeamNode, b: &BeamNode) -> [Vector3<f64>; 8] {
        let [ax, ay, az] = a.reference_gradients;
        let [bx, by, bz] = b.reference_gradients;
        [
            a.reference_position,
            ax,
            ay,
            az,
            b.reference_position,
            bx,
            by,
            bz,
        ]
    }

    /// Rebuild every element with `quadrature` (same nodes and sections).
    pub fn set_quadrature(&mut self, quadrature: BeamQuadrature) -> Result<()> {
        for el in &mut self.elements {
            let [a, b] = el.nodes;
            let reference = Self::reference_vectors(&self.nodes[a], &self.nodes[b]);
            *el = AncfBeam::new(el.nodes, &reference, el.length(), *el.section(), quadrature)?;
        }
        Ok(())
    }

    fn node_mut(&mut self, n: NodeId) -> Result<&mut BeamNode> {
        let count = self.nodes.len();
        self.nodes.get_mut(n.0).ok_or_else(|| {
            FeaError::invalid("node", n.0, format!("no such node (the mesh has {count})"))
        })
    }

    /// The node `n`.
    pub fn node(&self, n: NodeId) -> Result<&BeamNode> {
        self.nodes.get(n.0).ok_or_else(|| {
            FeaError::invalid(
                "node",
                n.0,
                format!("no such node (the mesh has {})", self.nodes.len()),
            )
        })
    }

    /// All nodes.
    pub fn nodes(&self) -> &[BeamNode] {
        &self.nodes
    }

    /// All elements.
    pub fn elements(&self) -> &[AncfBeam] {
        &self.elements
    }

    /// Clamp node `n`: hold all 12 coordinates (position and the whole frame
    /// `r_x`, `r_y`, `r_z`, any orientation).
    pub fn clamp(&mut self, n: NodeId) -> Result<()> {
        self.node_mut(n)?.fixed = [true; 12];
        Ok(())
    }

    /// Hold the position of node `n` (its gradients stay free).
    pub fn fix_position(&mut self, n: NodeId) -> Result<()> {
        self.node_mut(n)?.fixed[..3].fill(true);
        Ok(())
    }

    /// Hold coordinate `k` (0..12: `r`, `r_x`, `r_y`, `r_z`, 3 components each) of node `n`.
    pub fn fix_coordinate(&mut self, n: NodeId, k: usize) -> Result<()> {
        if k >= BeamNode::NDOF {
            return Err(FeaError::invalid("coordinate", k, "must be in 0..12"));
        }
        self.node_mut(n)?.fixed[k] = true;
        Ok(())
    }

    /// Set the applied (dead) force on node `n`, N.
    pub fn set_force(&mut self, n: NodeId, force: Vector3<f64>) -> Result<()> {
        finite3("node.force", &force)?;
        self.node_mut(n)?.force = force;
        Ok(())
    }

    /// Set an applied (dead) couple `torque` (N m) on node `n`: the generalized forces
    /// `Q_k = (T x d_k) / 2` on its gradients, `d_k` the node's reference frame
    /// `[r_x, r_y, r_z]`. Their virtual work on an infinitesimal rotation `dtheta` of the
    /// frame (`d(d_k) = dtheta x d_k`) is `sum_k Q_k . (dtheta x d_k) = dtheta .
    /// sum_k (T - d_k (d_k . T)) / 2 = T . dtheta` (orthonormal frame): the moment `T`.
    /// The forces keep their direction (a dead couple), exact for small rotations.
    pub fn set_torque(&mut self, n: NodeId, torque: Vector3<f64>) -> Result<()> {
        finite3("node.torque", &torque)?;
        let node = self.node_mut(n)?;
        node.gradient_force = node.reference_gradients.map(|d| 0.5 * torque.cross(&d));
        Ok(())
    }

    /// Set the gravity acceleration, m/s^2.
    pub fn set_gravity(&mut self, gravity: Vector3<f64>) -> Result<()> {
        finite3("gravity", &gravity)?;
        self.gravity = gravity;
        Ok(())
    }

    /// Number of global coordinates (12 per node).
    pub fn ndof(&self) -> usize {
        BeamNode::NDOF * self.nodes.len()
    }

    /// Total reference mass, kg.
    pub fn total_mass(&self) -> f64 {
        self.elements.iter().map(AncfBeam::mass).sum()
    }

    /// The numbering of the free coordinates.
    pub fn dof_map(&self) -> DofMap {
        DofMap::from_fixed(self.nodes.iter().flat_map(|n| n.fixed))
    }

    /// The global coordinate vector `q` of the current configuration.
    pub fn coordinates(&self) -> Vec<f64> {
        let mut q = Vec::with_capacity(self.ndof());
        for n in &self.nodes {
            q.extend_from_slice(n.position.as_slice());
            for g in &n.gradients {
                q.extend_from_slice(g.as_slice());
            }
        }
        q
    }

    /// Set the current configuration from a global coordinate vector (length
    /// [`ndof`](Self::ndof), finite).
    pub fn set_coordinates(&mut self, q: &[f64]) -> Result<()> {
        crate::error::check_coordinates(q, self.ndof(), BeamNode::NDOF)?;
        for (n, node) in self.nodes.iter_mut().enumerate() {
            let v = |k: usize| {
                Vector3::new(
                    q[12 * n + 3 * k],
                    q[12 * n + 3 * k + 1],
                    q[12 * n + 3 * k + 2],
                )
            };
            node.position = v(0);
            node.gradients = [v(1), v(2), v(3)];
        }
        Ok(())
    }

    /// The 24 coordinates of element `el` from the global vector `q`.
    pub fn element_coordinates(el: &AncfBeam, q: &[f64]) -> BeamVector {
        BeamVector::from_fn(|i, _| q[12 * el.nodes[i / 12] + i % 12])
    }

    /// The applied loads at load factor `lambda`: `lambda (F_nodal + Q_couples +
    /// Q_gravity)`, global (N on position rows, N m on gradient rows).
    pub fn external_force(&self, lambda: f64) -> Vec<f64> {
        let mut f = vec![0.0; self.ndof()];
        for (n, node) in self.nodes.iter().enumerate() {
            for i in 0..3 {
                f[12 * n + i] += lambda * node.force[i];
                for k in 0..3 {
                    f[12 * n + 3 * (k + 1) + i] += lambda * node.gradient_force[k][i];
                }
            }
        }
        if self.gravity != Vector3::zeros() {
            for el in &self.elements {
                let qg = el.gravity_force(&self.gravity);
                for i in 0..24 {
                    f[12 * el.nodes[i / 12] + i % 12] += lambda * qg[i];
                }
            }
        }
        f
    }

    /// The global internal force `Q(q)` and, if `tangent`, the tangent stiffness on the
    /// free coordinates of `map`.
    pub fn internal_force(
        &self,
        q: &[f64],
        map: &DofMap,
        tangent: bool,
    ) -> Result<(Vec<f64>, Option<SparseMatrix>)> {
        let mut f = vec![0.0; self.ndof()];
        let mut trip = Vec::new();
        if tangent {
            trip.reserve(576 * self.elements.len());
        }
        for el in &self.elements {
            let e = Self::element_coordinates(el, q);
            let (qe, ke) = el.force_and_tangent(&e, tangent);
            for i in 0..24 {
                f[12 * el.nodes[i / 12] + i % 12] += qe[i];
            }
            if tangent {
                scatter_element_matrix(&el.nodes, 12, &ke, map, &mut trip);
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
    pub fn mass_matrix(&self, map: &DofMap) -> Result<SparseMatrix> {
        let mut trip = Vec::new();
        for el in &self.elements {
            scatter_element_matrix(&el.nodes, 12, &el.mass_matrix(), map, &mut trip);
        }
        sparse(map.nfree(), &trip)
    }

    /// Strain energy of the current configuration, J.
    pub fn strain_energy(&self) -> f64 {
        let q = self.coordinates();
        self.elements
            .iter()
            .map(|el| el.strain_energy(&Self::element_coordinates(el, &q)))
            .sum()
    }
}

crate::statics::static_model_via_inherent!(BeamMesh {
    /// `max_e E A`, N.
    fn force_scale(&self) -> f64 {
        self.elements
            .iter()
            .map(|e| e.section().young * e.section().area)
            .fold(0.0, f64::max)
    }
});

#[cfg(test)]
#[path = "beam_mesh_tests.rs"]
mod tests;
