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
//! ([`SparseSpd`](crate::SparseSpd): symbolic Cholesky once, numeric refactorization
//! every step into the same buffers; the element matrices are scattered through a precomputed index map, so a
//! step allocates nothing; this bookkeeping is shared with the other mesh items,
//! `crate::implicit`). Supported coordinates ([`TetMesh::fix_node`] ...) are removed
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

use chrono_core::collision::{CollisionProxy, ProxyShape};
use chrono_core::descriptor::{BlockId, CcpProblem, ConstraintRows, Variables};
use chrono_core::item::{PhysicsItem, StepContext};
use chrono_core::{ContactMaterial, Result as CoreResult};
use nalgebra::Vector3;

use crate::dynamics::{AttachTarget, Attachment};
use crate::element::Tet4;
use crate::error::{FeaError, Result, finite3, positive};
use crate::implicit::{ImplicitBlock, core_error};
use crate::mesh::DofMap;
use crate::node::NodeId;
use crate::tet_mesh::TetMesh;

const EL: usize = Tet4::NDOF;

/// A [`TetMesh`] stepped implicitly in the system's CCP (see the module docs).
#[derive(Debug)]
pub struct TetItem {
    name: String,
    mesh: TetMesh,
    core: ImplicitBlock,
    /// Nodes of the boundary triangles (the contact spheres), ascending.
    surface: Vec<usize>,
    /// Radius of the contact spheres, m (`None`: no contact).
    contact_radius: Option<f64>,
    contact_material: ContactMaterial,
}

impl TetItem {
    /// The item for `mesh` (supports taken now; the mesh starts at rest). Errors: no
    /// element, every coordinate supported.
    pub fn new(name: impl Into<String>, mesh: TetMesh) -> Result<Self> {
        let name = name.into();
        let els = mesh.elements();
        let core = ImplicitBlock::new(
            name.clone(),
            mesh.dof_map(),
            els.len(),
            EL,
            |e, a| 3 * els[e].nodes[a / 3] + a % 3,
            |e| els[e].mass_matrix(),
        )?;
        let all: Vec<NodeId> = (0..mesh.nodes().len()).map(NodeId).collect();
        let mut surface: Vec<usize> = mesh
            .boundary_triangles(&all)
            .into_iter()
            .flatten()
            .collect();
        surface.sort_unstable();
        surface.dedup();
        Ok(Self {
            name,
            mesh,
            core,
            surface,
            contact_radius: None,
            contact_material: ContactMaterial::default(),
        })
    }

    /// Attach a node's position to `target` (see the module docs); returns its index.
    /// Errors: unknown node, non-finite point. A body handle is checked at the step.
    pub fn attach(&mut self, node: NodeId, target: AttachTarget) -> Result<usize> {
        self.mesh.node(node)?;
        self.core.attach(node, target)
    }

    /// The attachments.
    pub fn attachments(&self) -> &[Attachment] {
        &self.core.attachments
    }

    /// The force of attachment `i` on its node during the last step (`gamma / h`), N.
    pub fn reaction(&self, i: usize) -> Option<Vector3<f64>> {
        self.core.reaction(i)
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
        &self.core.map
    }

    /// Velocity of node `n`, m/s.
    pub fn node_velocity(&self, n: NodeId) -> Result<Vector3<f64>> {
        self.mesh.node(n)?;
        Ok(Vector3::from_column_slice(
            &self.core.velocity[3 * n.0..3 * n.0 + 3],
        ))
    }

    /// Set the velocity of node `n` (m/s); components on supported coordinates must be 0
    /// (the error names the node and component).
    pub fn set_node_velocity(&mut self, n: NodeId, velocity: Vector3<f64>) -> Result<()> {
        self.mesh.node(n)?;
        finite3("node.velocity", &velocity)?;
        self.core.set_velocity(
            3 * n.0,
            velocity.as_slice(),
            &format!("node {} velocity", n.0),
        )
    }

    /// Set the configuration (all coordinates, [`TetMesh::set_coordinates`]); the
    /// velocities are kept.
    pub fn set_coordinates(&mut self, q: &[f64]) -> Result<()> {
        self.mesh.set_coordinates(q)
    }

    /// Kinetic energy `v' M v / 2` (consistent mass), J.
    pub fn kinetic_energy(&self) -> f64 {
        self.core.kinetic_energy()
    }

    /// Linear momentum `sum_ab M_ab v_b` of the free coordinates, kg m/s (the supported
    /// nodes are at rest).
    pub fn linear_momentum(&self) -> Vector3<f64> {
        self.core.momentum(|g| Some(g % 3))
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
}

impl PhysicsItem for TetItem {
    fn name(&self) -> &str {
        &self.name
    }

    /// Assemble `F_ext + F_g - Q(q)` and `H = M + (h^2 + h beta) K` at `q(l)`, refactorize.
    fn begin_step(&mut self, ctx: &StepContext) -> CoreResult<()> {
        let h = ctx.h;
        let core = &mut self.core;
        for (n, node) in self.mesh.nodes().iter().enumerate() {
            core.q[3 * n..3 * n + 3].copy_from_slice(node.position.as_slice());
            core.force[3 * n..3 * n + 3].copy_from_slice(node.force.as_slice());
        }
        core.begin_assembly();
        for (e, el) in self.mesh.elements().iter().enumerate() {
            let x = TetMesh::element_coordinates(el, &core.q);
            let (qe, ke) = el.force_and_tangent(&x, true);
            let w = ctx.gravity * (el.mass() / 4.0);
            core.add_element_matrix(e, &ke, h * h + h * el.material().damping);
            for a in 0..EL {
                core.force[3 * el.nodes[a / 3] + a % 3] += w[a % 3] - qe[a];
            }
        }
        core.finish_assembly(ctx, 3)
    }

    fn add_variables(&mut self, vars: &mut Variables) {
        self.core.add_variables(vars);
    }

    /// `k = M v + h (F_ext + F_g - Q(q))` on the free coordinates.
    fn load_momentum(&self, ctx: &StepContext, vars: &Variables, k: &mut [f64]) {
        self.core.load_momentum(ctx, vars, k);
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
        if node < self.mesh.nodes().len() {
            self.core.point_jacobian(&[(3 * node, 1.0)], dirs, entry);
        }
        [0.0; 3]
    }

    fn add_body_constraints(
        &mut self,
        ctx: &StepContext,
        bodies: &chrono_core::Bodies,
        _vars: &Variables,
        rows: &mut ConstraintRows,
    ) -> CoreResult<()> {
        let nodes = self.mesh.nodes();
        self.core
            .attachment_rows(ctx, bodies, rows, 3, |n| Ok(nodes[n].position))
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
        if self.core.advance(ctx, vars, v, problem, gamma, 3)? {
            self.mesh
                .set_coordinates(&self.core.q)
                .map_err(core_error)?;
        }
        Ok(())
    }
}
