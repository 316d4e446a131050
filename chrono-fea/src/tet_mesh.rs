//! A mesh of linear tetrahedra ([`Tet4`]): nodes, elements, supports, loads and the
//! global (sparse) assembly of forces, tangent stiffness and mass.
//!
//! Global coordinates: node `n` owns `q[3 n .. 3 n + 3]`, its position. Supports hold
//! coordinates at their current values (a clamp or a prescribed displacement: move the
//! node, then fix it); the free coordinates are numbered by a [`DofMap`]. The mesh is
//! solved statically by [`solve_static`](crate::statics::solve_static) (it implements
//! [`StaticModel`](crate::statics::StaticModel)). Box meshes with named faces come from
//! [`BoxMesh`](crate::tet_box::BoxMesh).

use nalgebra::{Matrix3, Vector3};

use crate::element::{Tet4, TetVector, von_mises};
use crate::error::{FeaError, Result, finite3};
use crate::material::SolidMaterial;
use crate::mesh::{DofMap, SparseMatrix, scatter_element_matrix, sparse};
use crate::node::{NodeId, SolidNode};

/// A mesh of linear tetrahedra (see the module docs).
#[derive(Debug, Clone, Default)]
pub struct TetMesh {
    nodes: Vec<SolidNode>,
    elements: Vec<Tet4>,
    gravity: Vector3<f64>,
}

impl TetMesh {
    /// An empty mesh without gravity.
    pub fn new() -> Self {
        Self::default()
    }

    /// Add a free, unloaded node at reference position `position` (m).
    pub fn add_node(&mut self, position: Vector3<f64>) -> Result<NodeId> {
        finite3("node.position", &position)?;
        self.nodes.push(SolidNode::new(position));
        Ok(NodeId(self.nodes.len() - 1))
    }

    /// Add a tetrahedron on four nodes (right-handed reference edges from the first
    /// node, see [`Tet4::new`]); its reference shape is taken from the nodes' reference
    /// positions. Errors name the element: unknown or repeated node, a degenerate or
    /// inverted shape, an invalid material.
    pub fn add_tet(&mut self, nodes: [NodeId; 4], material: SolidMaterial) -> Result<usize> {
        let index = self.elements.len();
        for (k, n) in nodes.iter().enumerate() {
            if n.0 >= self.nodes.len() {
                return Err(FeaError::invalid(
                    format!("element {index}.node[{k}]"),
                    n.0,
                    format!("no such node (the mesh has {})", self.nodes.len()),
                ));
            }
            if nodes[..k].contains(n) {
                return Err(FeaError::invalid(
                    format!("element {index}.node[{k}]"),
                    n.0,
                    "the four nodes must differ",
                ));
            }
        }
        let ids = nodes.map(|n| n.0);
        let x = ids.map(|n| self.nodes[n].reference_position);
        let el = Tet4::new(ids, &x, material).map_err(|e| match e {
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
        })?;
        self.elements.push(el);
        Ok(index)
    }

    fn node_mut(&mut self, n: NodeId) -> Result<&mut SolidNode> {
        let count = self.nodes.len();
        self.nodes.get_mut(n.0).ok_or_else(|| {
            FeaError::invalid("node", n.0, format!("no such node (the mesh has {count})"))
        })
    }

    /// The node `n`.
    pub fn node(&self, n: NodeId) -> Result<&SolidNode> {
        self.nodes.get(n.0).ok_or_else(|| {
            FeaError::invalid(
                "node",
                n.0,
                format!("no such node (the mesh has {})", self.nodes.len()),
            )
        })
    }

    /// All nodes.
    pub fn nodes(&self) -> &[SolidNode] {
        &self.nodes
    }

    /// All elements.
    pub fn elements(&self) -> &[Tet4] {
        &self.elements
    }

    /// Hold all three coordinates of node `n` at their current values.
    pub fn fix_node(&mut self, n: NodeId) -> Result<()> {
        self.node_mut(n)?.fixed = [true; 3];
        Ok(())
    }

    /// Hold coordinate `axis` (0, 1, 2 = x, y, z) of node `n` at its current value (a
    /// roller support).
    pub fn fix_coordinate(&mut self, n: NodeId, axis: usize) -> Result<()> {
        if axis > 2 {
            return Err(FeaError::invalid("axis", axis, "must be 0, 1 or 2"));
        }
        self.node_mut(n)?.fixed[axis] = true;
        Ok(())
    }

    /// Move node `n` to `position` (m) without changing its reference position (a
    /// prescribed displacement when the node is then fixed).
    pub fn set_position(&mut self, n: NodeId, position: Vector3<f64>) -> Result<()> {
        finite3("node.position", &position)?;
        self.node_mut(n)?.position = position;
        Ok(())
    }

    /// Set the applied (dead) force on node `n`, N.
    pub fn set_force(&mut self, n: NodeId, force: Vector3<f64>) -> Result<()> {
        finite3("node.force", &force)?;
        self.node_mut(n)?.force = force;
        Ok(())
    }

    /// The boundary triangles whose three nodes are all in `set` (faces of exactly one
    /// element), oriented with the outward normal, as node triples. For a plane face of
    /// a convex body this is the triangulation of that face.
    pub fn boundary_triangles(&self, set: &[NodeId]) -> Vec<[usize; 3]> {
        let mut in_set = vec![false; self.nodes.len()];
        for n in set {
            if let Some(s) = in_set.get_mut(n.0) {
                *s = true;
            }
        }
        // Faces opposite each node, outward for a right-handed tet.
        const FACES: [[usize; 3]; 4] = [[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]];
        let mut faces: Vec<([usize; 3], [usize; 3])> = Vec::new();
        for el in &self.elements {
            for f in FACES {
                let tri = f.map(|k| el.nodes[k]);
                if tri.iter().all(|&n| in_set[n]) {
                    let mut key = tri;
                    key.sort_unstable();
                    faces.push((key, tri));
                }
            }
        }
        faces.sort_unstable_by_key(|f| f.0);
        let mut out = Vec::new();
        let mut i = 0;
        while i < faces.len() {
            let mut j = i + 1;
            while j < faces.len() && faces[j].0 == faces[i].0 {
                j += 1;
            }
            if j == i + 1 {
                out.push(faces[i].1);
            }
            i = j;
        }
        out
    }

    /// Add a uniform dead traction `traction` (Pa, per reference area) on the boundary
    /// triangles of `set` ([`boundary_triangles`](Self::boundary_triangles)) to the nodal
    /// forces: each triangle of reference area `A` gives `A t / 3` to each of its nodes
    /// (the consistent load of the linear element). Returns the total area, m^2.
    pub fn add_traction(&mut self, set: &[NodeId], traction: Vector3<f64>) -> Result<f64> {
        finite3("traction", &traction)?;
        let tris = self.boundary_triangles(set);
        if tris.is_empty() {
            return Err(FeaError::invalid(
                "traction.set",
                format!("{} nodes", set.len()),
                "holds no boundary triangle",
            ));
        }
        let mut total = 0.0;
        for t in tris {
            let x = t.map(|n| self.nodes[n].reference_position);
            let area = 0.5 * (x[1] - x[0]).cross(&(x[2] - x[0])).norm();
            total += area;
            for n in t {
                self.nodes[n].force += traction * (area / 3.0);
            }
        }
        Ok(total)
    }

    /// Set the gravity acceleration, m/s^2 (a body force `rho g`).
    pub fn set_gravity(&mut self, gravity: Vector3<f64>) -> Result<()> {
        finite3("gravity", &gravity)?;
        self.gravity = gravity;
        Ok(())
    }

    /// The gravity acceleration, m/s^2.
    pub fn gravity(&self) -> Vector3<f64> {
        self.gravity
    }

    /// Number of global coordinates (3 per node).
    pub fn ndof(&self) -> usize {
        SolidNode::NDOF * self.nodes.len()
    }

    /// Total reference volume, m^3.
    pub fn volume(&self) -> f64 {
        self.elements.iter().map(Tet4::volume).sum()
    }

    /// Total mass `sum rho V`, kg.
    pub fn total_mass(&self) -> f64 {
        self.elements.iter().map(Tet4::mass).sum()
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
        }
        q
    }

    /// Set the current configuration from a global coordinate vector (length
    /// [`ndof`](Self::ndof), finite).
    pub fn set_coordinates(&mut self, q: &[f64]) -> Result<()> {
        crate::error::check_coordinates(q, self.ndof(), 3)?;
        for (n, node) in self.nodes.iter_mut().enumerate() {
            node.position = Vector3::new(q[3 * n], q[3 * n + 1], q[3 * n + 2]);
        }
        Ok(())
    }

    /// The 12 coordinates of element `el` taken from the global vector `q`.
    pub fn element_coordinates(el: &Tet4, q: &[f64]) -> TetVector {
        TetVector::from_fn(|i, _| q[3 * el.nodes[i / 3] + i % 3])
    }

    /// The current coordinates of element `e`.
    pub fn current_element_coordinates(&self, e: usize) -> TetVector {
        let el = &self.elements[e];
        TetVector::from_fn(|i, _| self.nodes[el.nodes[i / 3]].position[i % 3])
    }

    /// The applied load at load factor `lambda`: `lambda (F_nodal + F_gravity)`, global, N.
    pub fn external_force(&self, lambda: f64) -> Vec<f64> {
        let mut f = vec![0.0; self.ndof()];
        for (n, node) in self.nodes.iter().enumerate() {
            for i in 0..3 {
                f[3 * n + i] += lambda * node.force[i];
            }
        }
        if self.gravity != Vector3::zeros() {
            for el in &self.elements {
                let w = self.gravity * (lambda * el.mass() / 4.0);
                for &n in &el.nodes {
                    for i in 0..3 {
                        f[3 * n + i] += w[i];
                    }
                }
            }
        }
        f
    }

    /// The global internal force `Q(q)` and, if `tangent`, the tangent stiffness on the
    /// free coordinates of `map` (sparse, duplicates summed).
    pub fn internal_force(
        &self,
        q: &[f64],
        map: &DofMap,
        tangent: bool,
    ) -> Result<(Vec<f64>, Option<SparseMatrix>)> {
        let mut f = vec![0.0; self.ndof()];
        let mut trip = Vec::new();
        if tangent {
            trip.reserve(144 * self.elements.len());
        }
        for el in &self.elements {
            let x = Self::element_coordinates(el, q);
            let (qe, ke) = el.force_and_tangent(&x, tangent);
            for i in 0..12 {
                f[3 * el.nodes[i / 3] + i % 3] += qe[i];
            }
            if tangent {
                scatter_element_matrix(&el.nodes, 3, &ke, map, &mut trip);
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
        let mut trip = Vec::with_capacity(144 * self.elements.len());
        for el in &self.elements {
            scatter_element_matrix(&el.nodes, 3, &el.mass_matrix(), map, &mut trip);
        }
        sparse(map.nfree(), &trip)
    }

    /// Strain energy of the current configuration, J.
    pub fn strain_energy(&self) -> f64 {
        (0..self.elements.len())
            .map(|e| self.elements[e].strain_energy(&self.current_element_coordinates(e)))
            .sum()
    }

    /// Cauchy stress of each element in the current configuration, Pa.
    pub fn cauchy_stresses(&self) -> Vec<Matrix3<f64>> {
        (0..self.elements.len())
            .map(|e| self.elements[e].cauchy_stress(&self.current_element_coordinates(e)))
            .collect()
    }

    /// Von Mises stress of each element in the current configuration, Pa.
    pub fn von_mises_stresses(&self) -> Vec<f64> {
        self.cauchy_stresses().iter().map(von_mises).collect()
    }
}

crate::statics::static_model_via_inherent!(TetMesh {
    /// `max_e (E V^(1/3)) x max(|X|)`, N: the stiffest element (stiffness `~ E V^(1/3)`,
    /// N/m) displaced by the largest reference coordinate. Positions are absolute, so
    /// their round-off (`1e-16 |X|`) times the stiffness is the floor of the residual.
    fn force_scale(&self) -> f64 {
        let extent = self
            .nodes
            .iter()
            .map(|n| n.reference_position.amax())
            .fold(0.0, f64::max);
        self.elements
            .iter()
            .map(|e| {
                let size = e.volume().cbrt();
                e.material().young * size * extent.max(size)
            })
            .fold(0.0, f64::max)
    }
});
