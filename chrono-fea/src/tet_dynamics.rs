//! A tetrahedral mesh as a [`PhysicsItem`]: implicit dynamics in the system's CCP.
//!
//! The same step as the cable item ([`CableItem`](crate::CableItem), see
//! [`dynamics`](crate::dynamics)): linearized implicit Euler,
//!
//! ```text
//! (M + h R + h^2 K) v+ = M v + h (F_ext + F_g - Q(q)) + D gamma,    q+ = q + h v+
//! ```
//!
//! with `M` the consistent mass of the tetrahedra ([`Tet4::mass_matrix`]), `Q` their
//! elastic force and `K = dQ/dq` its exact tangent (material + geometric,
//! [`Tet4::force_and_tangent`]), `R = beta K` (`beta` = [`SolidMaterial::damping`] of each
//! element), `F_ext` the nodal dead loads of the mesh and `F_g = rho V g / 4` per node
//! from the system's gravity. `H = M + h R + h^2 K` is the block's coupled mass operator
//! ([`SparseSpd`]: symbolic Cholesky once, numeric refactorization every step into the same
//! buffers; the element matrices are scattered through a precomputed index map, so a
//! step allocates nothing). Supported coordinates ([`TetMesh::fix_node`] ...) are removed
//! from the block and stay where they are.
//!
//! # Attachments and contact
//!
//! As for the cable: an [`Attachment`] ties a node's position to a fixed world point or a
//! point of a rigid body by three bilateral rows `d . (x_node - p) = 0` (`d` the world
//! axes), `b = d . (x_node - p) / h` minus a kinematic body's known velocity; the
//! reactions are `gamma / h`. With [`TetItem::set_contact_spheres`] every surface node
//! (a node of a boundary triangle) is a sphere proxy of the given radius against the
//! body colliders, id = node index; the item's side of a contact row along `d` is `d` on
//! the node's free coordinates (no coefficient on a supported one). The spheres sit
//! on the nodes: the contact surface is offset outwards by the radius and is only as
//! fine as the node spacing (no triangle–collider contact yet).
//!
//! [`SolidMaterial::damping`]: crate::material::SolidMaterial::damping

use std::sync::Arc;

use std::sync::Mutex;

use chrono_core::body::RigidBody;
use chrono_core::collision::{CollisionProxy, ProxyShape};
use chrono_core::descriptor::{
    BlockId, CcpProblem, ConstraintRows, MassOperator, RowId, Variables,
};
use chrono_core::item::{PhysicsItem, StepContext};
use chrono_core::{ChronoError, ContactMaterial, Result as CoreResult};
use faer::sparse::{SparseColMat, Triplet};
use nalgebra::Vector3;

use crate::attach_rows::{AttachContext, push_attachment_rows};
use crate::dynamics::{AttachTarget, Attachment};
use crate::error::positive;

use crate::element::Tet4;
use crate::error::{FeaError, Result, finite3};
use crate::mesh::DofMap;
use crate::node::NodeId;
use crate::spd::{SparseSpd, symmetric_upper_mul};
use crate::tet_mesh::TetMesh;

const NONE: usize = usize::MAX;
const EL: usize = Tet4::NDOF;

/// A [`TetMesh`] stepped implicitly in the system's CCP (see the module docs).
#[derive(Debug)]
pub struct TetItem {
    name: String,
    mesh: TetMesh,
    map: DofMap,
    /// Global coordinate of each free index.
    free_global: Vec<usize>,
    /// Node velocities, all coordinates (0 on the supported ones), m/s.
    velocity: Vec<f64>,
    op: Arc<SparseSpd>,
    /// Consistent mass on the free coordinates (upper triangle, the pattern of `op`), kg.
    mass: SparseColMat<usize, f64>,
    /// For element `e` and local pair `(a, b)`: the index of the upper-triangle value it
    /// adds to (`NONE`: a supported coordinate or the lower triangle).
    scatter: Vec<usize>,
    h_values: Vec<f64>,
    /// `F_ext + F_g - Q(q)` at the start of the step (all coordinates), N.
    force: Vec<f64>,
    q: Vec<f64>,
    block: Option<BlockId>,
    attachments: Vec<Attachment>,
    /// Rows of this step, 3 per attachment (`None`: not needed).
    rows: Vec<Option<RowId>>,
    /// Attachment forces on the nodes from the last step, N.
    reactions: Vec<Vector3<f64>>,
    /// One row's coefficients on the block (`nfree`, scratch).
    coefs: Vec<f64>,
    /// Nodes of the boundary triangles (the contact spheres), ascending.
    surface: Vec<usize>,
    /// Radius of the contact spheres, m (`None`: no contact).
    contact_radius: Option<f64>,
    contact_material: ContactMaterial,
    /// The three rows of a proxy on the free coordinates (`3 nfree`, zero between
    /// calls): `proxy_jacobian` takes `&self`.
    jacobian: Mutex<Vec<f64>>,
}

impl TetItem {
    /// The item for `mesh` (supports taken now; the mesh starts at rest). Errors: no
    /// element, every coordinate supported.
    pub fn new(name: impl Into<String>, mesh: TetMesh) -> Result<Self> {
        if mesh.elements().is_empty() {
            return Err(FeaError::invalid("mesh.elements", 0, "needs an element"));
        }
        let map = mesh.dof_map();
        let n = map.nfree();
        if n == 0 {
            return Err(FeaError::invalid(
                "mesh",
                "all coordinates supported",
                "needs a free coordinate",
            ));
        }
        let free_global: Vec<usize> = (0..map.ndof())
            .filter(|&g| map.free_index(g).is_some())
            .collect();
        let gidx = |el: &Tet4, a: usize| 3 * el.nodes[a / 3] + a % 3;
        let mut trip: Vec<Triplet<usize, usize, f64>> =
            (0..n).map(|f| Triplet::new(f, f, 0.0)).collect();
        for el in mesh.elements() {
            for a in 0..EL {
                for b in 0..EL {
                    if let (Some(i), Some(j)) =
                        (map.free_index(gidx(el, a)), map.free_index(gidx(el, b)))
                        && i <= j
                    {
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
        let mut scatter = vec![NONE; mesh.elements().len() * EL * EL];
        let mut mass = pattern.clone();
        let mvals = mass.val_mut();
        mvals.fill(0.0);
        for (e, el) in mesh.elements().iter().enumerate() {
            let me = el.mass_matrix();
            for a in 0..EL {
                for b in 0..EL {
                    if let (Some(i), Some(j)) =
                        (map.free_index(gidx(el, a)), map.free_index(gidx(el, b)))
                        && i <= j
                    {
                        let idx = find(i, j);
                        scatter[(e * EL + a) * EL + b] = idx;
                        mvals[idx] += me[(a, b)];
                    }
                }
            }
        }
        let op = Arc::new(SparseSpd::new(pattern)?);
        let nnz = op.nnz();
        let ndof = mesh.ndof();
        let all: Vec<NodeId> = (0..mesh.nodes().len()).map(NodeId).collect();
        let mut surface: Vec<usize> = mesh
            .boundary_triangles(&all)
            .into_iter()
            .flatten()
            .collect();
        surface.sort_unstable();
        surface.dedup();
        Ok(Self {
            name: name.into(),
            mesh,
            map,
            free_global,
            velocity: vec![0.0; ndof],
            op,
            mass,
            scatter,
            h_values: vec![0.0; nnz],
            force: vec![0.0; ndof],
            q: vec![0.0; ndof],
            block: None,
            attachments: Vec::new(),
            rows: Vec::new(),
            reactions: Vec::new(),
            coefs: vec![0.0; n],
            surface,
            contact_radius: None,
            contact_material: ContactMaterial::default(),
            jacobian: Mutex::new(vec![0.0; 3 * n]),
        })
    }

    /// Attach a node's position to `target` (see the module docs); returns its index.
    /// Errors: unknown node, non-finite point. A body handle is checked at the step.
    pub fn attach(&mut self, node: NodeId, target: AttachTarget) -> Result<usize> {
        self.mesh.node(node)?;
        match &target {
            AttachTarget::Point(p) => finite3("attachment.point", p)?,
            AttachTarget::Body { local, .. } => finite3("attachment.local", local)?,
        }
        self.attachments.push(Attachment { node, target });
        self.reactions.push(Vector3::zeros());
        Ok(self.attachments.len() - 1)
    }

    /// The attachments.
    pub fn attachments(&self) -> &[Attachment] {
        &self.attachments
    }

    /// The force of attachment `i` on its node during the last step (`gamma / h`), N.
    pub fn reaction(&self, i: usize) -> Option<Vector3<f64>> {
        self.reactions.get(i).copied()
    }

    /// Make every surface node a contact sphere of `radius` (m, finite and > 0; the error
    /// names `contact.radius`) with the surface material `material` (checked with
    /// [`ContactMaterial::validate`]). Default: no contact.
    pub fn set_contact_spheres(&mut self, radius: f64, material: ContactMaterial) -> Result<()> {
        let radius = positive("contact.radius", radius)?;
        material.validate().map_err(|e| {
            FeaError::invalid("contact.material", e.to_string(), "rejected by chrono-core")
        })?;
        self.contact_radius = Some(radius);
        self.contact_material = material;
        Ok(())
    }

    /// Radius of the contact spheres, m (`None`: contact off).
    pub fn contact_radius(&self) -> Option<f64> {
        self.contact_radius
    }

    /// The surface nodes (nodes of boundary triangles): the contact spheres.
    pub fn surface_nodes(&self) -> &[usize] {
        &self.surface
    }

    /// The mesh (current configuration).
    pub fn mesh(&self) -> &TetMesh {
        &self.mesh
    }

    /// The numbering of the free coordinates (the dof of the item's block).
    pub fn dof_map(&self) -> &DofMap {
        &self.map
    }

    /// Velocity of node `n`, m/s.
    pub fn node_velocity(&self, n: NodeId) -> Result<Vector3<f64>> {
        self.mesh.node(n)?;
        Ok(Vector3::from_column_slice(
            &self.velocity[3 * n.0..3 * n.0 + 3],
        ))
    }

    /// Set the velocity of node `n` (m/s); components on supported coordinates must be 0
    /// (the error names the node and component).
    pub fn set_node_velocity(&mut self, n: NodeId, velocity: Vector3<f64>) -> Result<()> {
        self.mesh.node(n)?;
        finite3("node.velocity", &velocity)?;
        for k in 0..3 {
            if velocity[k] != 0.0 && self.map.free_index(3 * n.0 + k).is_none() {
                return Err(FeaError::invalid(
                    format!("node {} velocity[{k}]", n.0),
                    velocity[k],
                    "a supported coordinate cannot move",
                ));
            }
            self.velocity[3 * n.0 + k] = velocity[k];
        }
        Ok(())
    }

    /// Set the configuration (all coordinates, [`TetMesh::set_coordinates`]); the
    /// velocities are kept.
    pub fn set_coordinates(&mut self, q: &[f64]) -> Result<()> {
        self.mesh.set_coordinates(q)
    }

    /// Kinetic energy `v' M v / 2` (consistent mass), J.
    pub fn kinetic_energy(&self) -> f64 {
        let v: Vec<f64> = self.free_global.iter().map(|&g| self.velocity[g]).collect();
        let mut mv = vec![0.0; v.len()];
        symmetric_upper_mul(self.mass.as_ref(), &v, &mut mv);
        0.5 * v.iter().zip(&mv).map(|(a, b)| a * b).sum::<f64>()
    }

    /// Linear momentum `sum_ab M_ab v_b` of the free coordinates, kg m/s (the supported
    /// nodes are at rest).
    pub fn linear_momentum(&self) -> Vector3<f64> {
        let v: Vec<f64> = self.free_global.iter().map(|&g| self.velocity[g]).collect();
        let mut mv = vec![0.0; v.len()];
        symmetric_upper_mul(self.mass.as_ref(), &v, &mut mv);
        let mut p = Vector3::zeros();
        for (f, &g) in self.free_global.iter().enumerate() {
            p[g % 3] += mv[f];
        }
        p
    }

    /// Strain energy of the current configuration, J.
    pub fn strain_energy(&self) -> f64 {
        self.mesh.strain_energy()
    }

    /// Potential of gravity `g` (m/s^2): `-sum_e rho V g . (x_0 + x_1 + x_2 + x_3) / 4`
    /// (exact for the linear element), J.
    pub fn gravity_potential(&self, gravity: &Vector3<f64>) -> f64 {
        let nodes = self.mesh.nodes();
        -self
            .mesh
            .elements()
            .iter()
            .map(|el| {
                let c: Vector3<f64> = el.nodes.iter().map(|&n| nodes[n].position).sum();
                el.mass() * gravity.dot(&c) / 4.0
            })
            .sum::<f64>()
    }

    fn item_label(&self) -> String {
        format!("FEA item \"{}\"", self.name)
    }
}

impl PhysicsItem for TetItem {
    fn name(&self) -> &str {
        &self.name
    }

    /// Assemble `F_ext + F_g - Q(q)` and `H = M + (h^2 + h beta) K` at `q(l)`, refactorize.
    fn begin_step(&mut self, ctx: &StepContext) -> CoreResult<()> {
        let h = ctx.h;
        for (n, node) in self.mesh.nodes().iter().enumerate() {
            self.q[3 * n..3 * n + 3].copy_from_slice(node.position.as_slice());
            self.force[3 * n..3 * n + 3].copy_from_slice(node.force.as_slice());
        }
        self.h_values.copy_from_slice(self.mass.val());
        for (e, el) in self.mesh.elements().iter().enumerate() {
            let x = TetMesh::element_coordinates(el, &self.q);
            let (qe, ke) = el.force_and_tangent(&x, true);
            let w = ctx.gravity * (el.mass() / 4.0);
            let c = h * h + h * el.material().damping;
            for a in 0..EL {
                self.force[3 * el.nodes[a / 3] + a % 3] += w[a % 3] - qe[a];
                for b in 0..EL {
                    let idx = self.scatter[(e * EL + a) * EL + b];
                    if idx != NONE {
                        self.h_values[idx] += c * ke[(a, b)];
                    }
                }
            }
        }
        if let Some(i) = self.force.iter().position(|x| !x.is_finite()) {
            return Err(ChronoError::NonFinite {
                item: self.item_label(),
                step: ctx.step,
                time: ctx.time,
                what: format!("internal force (coordinate {i} of node {})", i / 3),
            });
        }
        self.op
            .refactor(&self.h_values)
            .map_err(|e| ChronoError::Diverged {
                item: self.item_label(),
                step: ctx.step,
                time: ctx.time,
                what: format!(
                    "iteration matrix M + h R + h^2 K (h = {h} s): {e}; reduce the step size"
                ),
            })
    }

    fn add_variables(&mut self, vars: &mut Variables) {
        self.block = Some(vars.add(MassOperator::Coupled(self.op.clone())));
    }

    /// `k = M v + h (F_ext + F_g - Q(q))` on the free coordinates.
    fn load_momentum(&self, ctx: &StepContext, vars: &Variables, k: &mut [f64]) {
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

    /// One sphere per surface node (id = node index) when contact is on.
    fn collision_proxies(&self, out: &mut Vec<CollisionProxy>) {
        let Some(radius) = self.contact_radius else {
            return;
        };
        let nodes = self.mesh.nodes();
        for &n in &self.surface {
            out.push(CollisionProxy {
                shape: ProxyShape::Sphere {
                    center: nodes[n].position,
                    radius,
                },
                material: self.contact_material,
                id: n as u32,
            });
        }
    }

    /// `d . x_dot` of the node: `d` on its free coordinates. No known velocity.
    fn proxy_jacobian(
        &self,
        proxy: u32,
        _p: &Vector3<f64>,
        dirs: &[Vector3<f64>; 3],
        entry: &mut dyn FnMut(BlockId, [&[f64]; 3]),
    ) -> [f64; 3] {
        let node = proxy as usize;
        let Some(blk) = self.block else {
            return [0.0; 3];
        };
        if node >= self.mesh.nodes().len() {
            return [0.0; 3];
        }
        let free: [Option<usize>; 3] = std::array::from_fn(|c| self.map.free_index(3 * node + c));
        if free.iter().all(Option::is_none) {
            return [0.0; 3];
        }
        let n = self.free_global.len();
        // A poisoned lock only means a panic elsewhere; the buffer is re-zeroed below.
        let mut buf = self.jacobian.lock().unwrap_or_else(|e| e.into_inner());
        for (c, f) in free.iter().enumerate() {
            if let Some(f) = *f {
                for (k, d) in dirs.iter().enumerate() {
                    buf[k * n + f] = d[c];
                }
            }
        }
        let (j0, rest) = buf.split_at(n);
        let (j1, j2) = rest.split_at(n);
        entry(blk, [j0, j1, j2]);
        for f in free.into_iter().flatten() {
            for k in 0..3 {
                buf[k * n + f] = 0.0;
            }
        }
        [0.0; 3]
    }

    fn add_body_constraints(
        &mut self,
        ctx: &StepContext,
        bodies: &[RigidBody],
        _vars: &Variables,
        rows: &mut ConstraintRows,
    ) -> CoreResult<()> {
        self.rows.clear();
        let Some(blk) = self.block else {
            return Ok(());
        };
        let label = self.item_label();
        let ctx = AttachContext {
            block: blk,
            bodies,
            h: ctx.h,
            label: &label,
        };
        let (mesh, map) = (&self.mesh, &self.map);
        self.coefs.fill(0.0);
        push_attachment_rows(
            &self.attachments,
            |n| Ok(mesh.nodes()[n].position),
            |n, d| map.free_index(3 * n + d),
            &ctx,
            &mut self.coefs,
            rows,
            &mut self.rows,
        )
    }

    /// `q+ = q + h v+`; the attachment forces `gamma / h`.
    fn update(
        &mut self,
        ctx: &StepContext,
        vars: &Variables,
        v: &[f64],
        problem: &CcpProblem,
        gamma: &[f64],
    ) -> CoreResult<()> {
        let Some(blk) = self.block else {
            return Ok(());
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
                item: self.item_label(),
                step: ctx.step,
                time: ctx.time,
                what: format!("coordinate {i} of node {}", i / 3),
            });
        }
        self.mesh
            .set_coordinates(&self.q)
            .map_err(|e| ChronoError::invalid("fea", e.to_string(), "rejected by chrono-fea"))?;
        for (ai, r) in self.reactions.iter_mut().enumerate() {
            *r = Vector3::zeros();
            for d in 0..3 {
                if let Some(Some(id)) = self.rows.get(3 * ai + d) {
                    r[d] = gamma[problem.row_index(*id)] / ctx.h;
                }
            }
        }
        Ok(())
    }
}
