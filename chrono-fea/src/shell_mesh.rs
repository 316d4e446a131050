//! A mesh of ANCF shell elements ([`AncfShell`]): nodes with a position and a
//! transverse gradient, elements, supports, nodal forces, follower pressure, and the
//! global (sparse) assembly of forces, tangent stiffness and mass.
//!
//! Global coordinates: node `n` owns `q[6 n .. 6 n + 6] = [r, d]`, its position (m) and
//! transverse gradient (`d = dr/dz`, the director; a [`GradientNode`] whose `slope` is
//! `d`). Supports hold coordinates at their current values: [`ShellMesh::fix_node`]
//! (a clamp: position and director), [`ShellMesh::fix_coordinate`] (one of the six, e.g.
//! a symmetry plane `x = 0` holds `r_x` and `d_x`). The mesh is solved by
//! [`solve_static`](crate::statics::solve_static): the nodal forces are dead loads, the
//! pressure is a follower load with its load stiffness
//! ([`StaticModel::follower_force`](crate::statics::StaticModel::follower_force)), gravity ([`ShellMesh::set_gravity`]) the consistent
//! body-force load [`AncfShell::gravity_force`]. In a system the mesh steps as a
//! [`ShellItem`](crate::ShellItem).
//!
//! [`ShellMesh::grid`] builds a structured mesh on a parametric surface (plates,
//! cylinders), [`ShellMesh::sphere_octant`] an octant of a sphere.

use nalgebra::Vector3;

use crate::element::{AncfShell, ShellLocking, ShellMaterial, ShellVector};
use crate::error::{FeaError, Result, finite3, positive};
use crate::mesh::{DofMap, SparseMatrix, scatter_element_matrix, sparse};
use crate::node::{GradientNode, NodeId};

/// A mesh of ANCF shell elements (see the module docs).
#[derive(Debug, Clone, Default)]
pub struct ShellMesh {
    nodes: Vec<GradientNode>,
    elements: Vec<AncfShell>,
    pressure: Vec<f64>,
    /// Gravity for the static solver, m/s^2 (the dynamic item takes the system's).
    gravity: Vector3<f64>,
}

impl ShellMesh {
    /// An empty mesh.
    pub fn new() -> Self {
        Self::default()
    }

    /// Add a free, unloaded node at reference position `position` (m) with the reference
    /// director `director` (normalized here; must be non-zero).
    pub fn add_node(&mut self, position: Vector3<f64>, director: Vector3<f64>) -> Result<NodeId> {
        finite3("node.position", &position)?;
        finite3("node.director", &director)?;
        let len = director.norm();
        if len <= 0.0 {
            return Err(FeaError::invalid(
                "node.director",
                "[0, 0, 0]",
                "must be non-zero",
            ));
        }
        self.nodes.push(GradientNode::new(position, director / len));
        Ok(NodeId(self.nodes.len() - 1))
    }

    /// Add an element on four nodes (counter-clockwise about the directors) of thickness
    /// `thickness` (m), both locking remedies on. Errors name the element and the field.
    pub fn add_element(
        &mut self,
        nodes: [NodeId; 4],
        thickness: f64,
        material: ShellMaterial,
    ) -> Result<usize> {
        self.add_element_with(nodes, thickness, material, ShellLocking::default())
    }

    /// [`add_element`](Self::add_element) with a choice of locking remedies.
    pub fn add_element_with(
        &mut self,
        nodes: [NodeId; 4],
        thickness: f64,
        material: ShellMaterial,
        locking: ShellLocking,
    ) -> Result<usize> {
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
        let d = ids.map(|n| self.nodes[n].reference_slope);
        let el =
            AncfShell::new(ids, &x, &d, thickness, material, locking).map_err(|e| match e {
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
        self.pressure.push(0.0);
        Ok(index)
    }

    /// Rebuild every element with the locking remedies `locking` (same nodes, thickness
    /// and material; from the nodes' reference configuration).
    pub fn set_locking(&mut self, locking: ShellLocking) -> Result<()> {
        for el in &mut self.elements {
            let x = el.nodes.map(|n| self.nodes[n].reference_position);
            let d = el.nodes.map(|n| self.nodes[n].reference_slope);
            *el = AncfShell::new(el.nodes, &x, &d, el.thickness(), *el.material(), locking)?;
        }
        Ok(())
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
    pub fn elements(&self) -> &[AncfShell] {
        &self.elements
    }

    /// Hold all six coordinates of node `n` (position and director): a clamp.
    pub fn fix_node(&mut self, n: NodeId) -> Result<()> {
        self.node_mut(n)?.fixed = [true; 6];
        Ok(())
    }

    /// Hold the position of node `n` (a pin; the director stays free).
    pub fn fix_position(&mut self, n: NodeId) -> Result<()> {
        let node = self.node_mut(n)?;
        node.fixed[..3].fill(true);
        Ok(())
    }

    /// Hold coordinate `k` of node `n`: 0..3 the position `x, y, z`, 3..6 the director
    /// components.
    pub fn fix_coordinate(&mut self, n: NodeId, k: usize) -> Result<()> {
        if k > 5 {
            return Err(FeaError::invalid("coordinate", k, "must be in 0..6"));
        }
        self.node_mut(n)?.fixed[k] = true;
        Ok(())
    }

    /// Symmetry about the plane `x_axis = const` through node `n`: hold the position
    /// component and the director component along `axis` (0, 1, 2).
    pub fn fix_symmetry(&mut self, n: NodeId, axis: usize) -> Result<()> {
        if axis > 2 {
            return Err(FeaError::invalid("axis", axis, "must be 0, 1 or 2"));
        }
        let node = self.node_mut(n)?;
        node.fixed[axis] = true;
        node.fixed[3 + axis] = true;
        Ok(())
    }

    /// Move node `n` to `position` (m) without changing its reference (a prescribed
    /// displacement when the node is then fixed).
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

    /// Set the follower pressure (Pa) on every element: along the current normal,
    /// towards the directors' side for `p > 0` (see
    /// [`AncfShell::pressure_force`]).
    pub fn set_pressure(&mut self, pressure: f64) -> Result<()> {
        if !pressure.is_finite() {
            return Err(FeaError::invalid("pressure", pressure, "must be finite"));
        }
        self.pressure.fill(pressure);
        Ok(())
    }

    /// The follower pressure of element `e`, Pa (`None`: no such element).
    pub fn element_pressure(&self, e: usize) -> Option<f64> {
        self.pressure.get(e).copied()
    }

    /// Set the gravity acceleration for the static solver, m/s^2 (a dead load, the
    /// consistent [`AncfShell::gravity_force`] of every element). A
    /// [`ShellItem`](crate::ShellItem) ignores it and uses the system's gravity.
    pub fn set_gravity(&mut self, gravity: Vector3<f64>) -> Result<()> {
        finite3("gravity", &gravity)?;
        self.gravity = gravity;
        Ok(())
    }

    /// The gravity of the static solver, m/s^2.
    pub fn gravity(&self) -> Vector3<f64> {
        self.gravity
    }

    /// Set the follower pressure (Pa) on element `e`.
    pub fn set_element_pressure(&mut self, e: usize, pressure: f64) -> Result<()> {
        if !pressure.is_finite() {
            return Err(FeaError::invalid("pressure", pressure, "must be finite"));
        }
        let count = self.elements.len();
        let slot = self.pressure.get_mut(e).ok_or_else(|| {
            FeaError::invalid(
                "element",
                e,
                format!("no such element (the mesh has {count})"),
            )
        })?;
        *slot = pressure;
        Ok(())
    }

    /// Number of global coordinates (6 per node).
    pub fn ndof(&self) -> usize {
        GradientNode::NDOF * self.nodes.len()
    }

    /// Total reference mid-surface area, m^2.
    pub fn area(&self) -> f64 {
        self.elements.iter().map(AncfShell::area).sum()
    }

    /// Total mass, kg.
    pub fn total_mass(&self) -> f64 {
        self.elements.iter().map(AncfShell::mass).sum()
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
            q.extend_from_slice(n.slope.as_slice());
        }
        q
    }

    /// Set the current configuration from a global coordinate vector.
    pub fn set_coordinates(&mut self, q: &[f64]) -> Result<()> {
        crate::error::check_coordinates(q, self.ndof(), 6)?;
        for (n, node) in self.nodes.iter_mut().enumerate() {
            node.position = Vector3::new(q[6 * n], q[6 * n + 1], q[6 * n + 2]);
            node.slope = Vector3::new(q[6 * n + 3], q[6 * n + 4], q[6 * n + 5]);
        }
        Ok(())
    }

    /// The 24 coordinates of element `el` from the global vector `q`.
    pub fn element_coordinates(el: &AncfShell, q: &[f64]) -> ShellVector {
        ShellVector::from_fn(|i, _| q[6 * el.nodes[i / 6] + i % 6])
    }

    /// The applied dead loads at load factor `lambda`: the nodal forces and gravity,
    /// global (N on positions, N m on directors).
    pub fn external_force(&self, lambda: f64) -> Vec<f64> {
        let mut f = vec![0.0; self.ndof()];
        for (n, node) in self.nodes.iter().enumerate() {
            for i in 0..3 {
                f[6 * n + i] = lambda * node.force[i];
            }
        }
        if self.gravity != Vector3::zeros() {
            for el in &self.elements {
                add_vector(el, &(lambda * el.gravity_force(&self.gravity)), &mut f);
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
            let x = Self::element_coordinates(el, q);
            let (qe, ke) = el.force_and_tangent(&x, tangent);
            add_vector(el, &qe, &mut f);
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

    /// The follower pressure force at load factor `lambda` (global, N) and, if
    /// `tangent`, its derivative on the free coordinates of `map`.
    pub fn pressure_force(
        &self,
        q: &[f64],
        lambda: f64,
        map: &DofMap,
        tangent: bool,
    ) -> Result<(Vec<f64>, Option<SparseMatrix>)> {
        let mut f = vec![0.0; self.ndof()];
        let mut trip = Vec::new();
        for (el, &p) in self.elements.iter().zip(&self.pressure) {
            if p == 0.0 {
                continue;
            }
            let x = Self::element_coordinates(el, q);
            let (fe, ke) = el.pressure_force(&x, lambda * p, tangent);
            add_vector(el, &fe, &mut f);
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
    pub fn mass_matrix(&self, map: &DofMap) -> Result<SparseMatrix> {
        let mut trip = Vec::with_capacity(576 * self.elements.len());
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
            .map(|el| el.strain_energy(&Self::element_coordinates(el, &q)))
            .sum()
    }

    /// A structured `nu x nv` mesh on the parametric surface `surface(u, v) ->
    /// (position, director)`, `u, v in [0, 1]`; node `(i, j)` is `NodeId(j (nu + 1) + i)`
    /// ([`grid_node`](Self::grid_node)). Elements run counter-clockwise in `(u, v)`, so
    /// the directors must point along `X_u x X_v`.
    pub fn grid(
        nu: usize,
        nv: usize,
        surface: impl Fn(f64, f64) -> (Vector3<f64>, Vector3<f64>),
        thickness: f64,
        material: ShellMaterial,
    ) -> Result<Self> {
        if nu == 0 {
            return Err(FeaError::invalid("grid.nu", nu, "must be >= 1"));
        }
        if nv == 0 {
            return Err(FeaError::invalid("grid.nv", nv, "must be >= 1"));
        }
        positive("section.thickness", thickness)?;
        let mut mesh = Self::new();
        for j in 0..=nv {
            for i in 0..=nu {
                let (x, d) = surface(i as f64 / nu as f64, j as f64 / nv as f64);
                mesh.add_node(x, d)?;
            }
        }
        for j in 0..nv {
            for i in 0..nu {
                let n = |a: usize, b: usize| Self::grid_node(nu, a, b);
                mesh.add_element(
                    [n(i, j), n(i + 1, j), n(i + 1, j + 1), n(i, j + 1)],
                    thickness,
                    material,
                )?;
            }
        }
        Ok(mesh)
    }

    /// The node `(i, j)` of a [`grid`](Self::grid) with `nu` elements along `u`.
    pub fn grid_node(nu: usize, i: usize, j: usize) -> NodeId {
        NodeId(j * (nu + 1) + i)
    }

    /// A flat rectangular plate `[0, lx] x [0, ly]` in the XY plane at `z = 0`, directors
    /// `+Z`, `nx x ny` elements (a [`grid`](Self::grid)).
    pub fn plate(
        lx: f64,
        ly: f64,
        nx: usize,
        ny: usize,
        thickness: f64,
        material: ShellMaterial,
    ) -> Result<Self> {
        positive("plate.lx", lx)?;
        positive("plate.ly", ly)?;
        Self::grid(
            nx,
            ny,
            |u, v| (Vector3::new(u * lx, v * ly, 0.0), Vector3::z()),
            thickness,
            material,
        )
    }

    /// The octant `x, y, z >= 0` of a sphere of mid-surface radius `radius` centred at the
    /// origin, directors outward: three `n x n` patches, the radial projections of the
    /// three quarter faces of the cube `[-1, 1]^3` at its `(1, 1, 1)` corner
    /// (equal-angle spacing), nodes on the shared edges merged. Returns the mesh; the
    /// nodes on the symmetry planes are found by their coordinates (`|x| < 1e-9 R`).
    pub fn sphere_octant(
        radius: f64,
        n: usize,
        thickness: f64,
        material: ShellMaterial,
    ) -> Result<Self> {
        let r = positive("sphere.radius", radius)?;
        if n == 0 {
            return Err(FeaError::invalid("sphere.n", n, "must be >= 1"));
        }
        positive("section.thickness", thickness)?;
        let mut mesh = Self::new();
        let mut ids: Vec<(Vector3<f64>, NodeId)> = Vec::new();
        let quarter = std::f64::consts::FRAC_PI_4;
        for face in 0..3 {
            let mut grid = vec![NodeId(0); (n + 1) * (n + 1)];
            for j in 0..=n {
                for i in 0..=n {
                    let a = (quarter * i as f64 / n as f64).tan();
                    let b = (quarter * j as f64 / n as f64).tan();
                    // Face `face` is the cube face normal to axis `face`; (a, b) on the
                    // next two axes, cyclically, so X_a x X_b points outward.
                    let mut c = Vector3::zeros();
                    c[face] = 1.0;
                    c[(face + 1) % 3] = a;
                    c[(face + 2) % 3] = b;
                    let dir = c.normalize();
                    let x = dir * r;
                    let found = ids.iter().find(|(p, _)| (p - x).norm() < 1e-9 * r);
                    let id = match found {
                        Some((_, id)) => *id,
                        None => {
                            let id = mesh.add_node(x, dir)?;
                            ids.push((x, id));
                            id
                        }
                    };
                    grid[j * (n + 1) + i] = id;
                }
            }
            for j in 0..n {
                for i in 0..n {
                    let g = |a: usize, b: usize| grid[b * (n + 1) + a];
                    mesh.add_element(
                        [g(i, j), g(i + 1, j), g(i + 1, j + 1), g(i, j + 1)],
                        thickness,
                        material,
                    )?;
                }
            }
        }
        Ok(mesh)
    }
}

fn add_vector(el: &AncfShell, v: &ShellVector, f: &mut [f64]) {
    for i in 0..24 {
        f[6 * el.nodes[i / 6] + i % 6] += v[i];
    }
}

crate::statics::static_model_via_inherent!(ShellMesh {
    /// `max_e (E_max t) x max(|X|, 1 m)`, N: the membrane stiffness of the stiffest
    /// element (N/m) times the size of the coordinates.
    fn force_scale(&self) -> f64 {
        let extent = self
            .nodes
            .iter()
            .map(|n| n.reference_position.amax())
            .fold(1.0, f64::max);
        self.elements
            .iter()
            .map(|e| e.material().elasticity().max() * e.thickness() * extent)
            .fold(0.0, f64::max)
    }
    fn follower_force(
        &self,
        q: &[f64],
        lambda: f64,
        map: &DofMap,
        tangent: bool,
    ) -> Result<Option<(Vec<f64>, Option<SparseMatrix>)>> {
        if self.pressure.iter().all(|&p| p == 0.0) {
            return Ok(None);
        }
        self.pressure_force(q, lambda, map, tangent).map(Some)
    }
});

impl crate::modal::MassModel for ShellMesh {
    fn mass_matrix(&self, map: &DofMap) -> Result<SparseMatrix> {
        ShellMesh::mass_matrix(self, map)
    }
}
