//! An ANCF shell mesh as a [`PhysicsItem`]: implicit dynamics in the system's CCP, with
//! gravity, follower pressure, damping, attachments and node contact spheres.
//!
//! # The step
//!
//! The linearized implicit Euler of the cable and the tetrahedra
//! ([`dynamics`](crate::dynamics)), for the 6 coordinates `[r, d]` of each node
//! ([`ShellMesh`]):
//!
//! ```text
//! (M + h R + h^2 K_T) v+ = M v + h (F_ext + F_g + F_p(q) - Q(q)) + D gamma,   q+ = q + h v+
//! ```
//!
//! - `M`: the consistent mass of the elements ([`AncfShell::mass_matrix`]), kg (kg m^2
//!   on the director rows, times the `z^2` moment).
//! - `Q`, `K = dQ/dq`: elastic force and its exact tangent ([`AncfShell::force_and_tangent`]);
//!   the five EAS parameters of each element are condensed inside that call at the
//!   configuration `q` of the start of the step (the condensation is exact for the
//!   St. Venant–Kirchhoff law, so nothing is carried from step to step).
//! - `F_ext`: the nodal dead forces of the mesh; `F_g`: the consistent gravity load of
//!   the system's gravity ([`AncfShell::gravity_force`]; the mesh's own
//!   [`ShellMesh::set_gravity`] is for the static solver and is ignored here).
//! - `F_p(q)`: the follower pressure of each element ([`AncfShell::pressure_force`]), with
//!   its load stiffness `K_p = dF_p/dq` in the tangent `K_T = K - sym(K_p)`.
//! - `R = beta K`: stiffness-proportional Rayleigh damping, `beta` in s
//!   ([`ShellItem::set_damping`]); it damps a mode of frequency `omega` with the damping
//!   ratio `beta omega / 2` and leaves rigid motion undamped.
//!
//! ## The non-symmetric load stiffness
//!
//! `H` is the coupled mass operator of the block and must be symmetric positive
//! definite (faer sparse Cholesky, [`SparseSpd`](crate::SparseSpd); the CCP needs
//! `N = D' H^-1 D` positive semidefinite). The element load stiffness `K_p` is not
//! symmetric. For a closed surface at constant pressure the pressure load is
//! conservative (potential `-p V`), so
//! the assembled `K_p` is symmetric and `sym(K_p) = K_p`: the skew parts of neighbouring
//! elements cancel. On an open surface (a tire cut at the rim, a membrane edge) a skew
//! part remains at the boundary; the item keeps the symmetric part `(K_p + K_p')/2` in
//! `H` and drops the skew part, i.e. that part of the load is integrated explicitly
//! (its value `F_p(q)` at the start of the step is exact; only its linearization is
//! incomplete). Dropping `K_p` altogether would leave the destabilizing pressure
//! stiffness (of order `p` times the element size) explicit, a stability limit on `h`.
//!
//! # Attachments and contact
//!
//! As for the other items: an [`Attachment`] ties a node's position to a fixed point or
//! a point of a rigid body by three bilateral rows; the director stays free (a hinge about
//! a line of attached nodes). [`ShellItem::attach_director`] ties the director too (a
//! clamp; all three components, so the thickness stretch at the node is held as well):
//! `d - a = 0` per axis with `a` a fixed direction or `R a_local` of a rigid body, the
//! body's side `-(a x e_c) . omega`, stabilized as the position rows (`C / h`). With
//! [`ShellItem::set_contact_spheres`] every node is a sphere proxy of the given radius
//! (id = node index) against the body colliders; the item's side of a contact row along
//! `d` is `d` on the node's free position coordinates. The spheres sit on the nodes: a
//! radius of `t / 2` puts the contact surface at the outer face of the shell where the
//! node touches, and between nodes the bilinear mid surface is straight, so a flat
//! collider cannot pass between the nodes of an element lying on it.

use chrono_core::body::BodyHandle;
use chrono_core::collision::{CollisionProxy, ProxyShape};
use chrono_core::descriptor::{BlockId, CcpProblem, ConstraintRows, RowId, Variables};
use chrono_core::item::{PhysicsItem, StepContext};
use chrono_core::{ContactMaterial, Result as CoreResult};
use nalgebra::Vector3;

use crate::attach_rows::{AttachContext, push_director_rows};
use crate::dynamics::{AttachTarget, Attachment};
use crate::element::{AncfShell, ShellMatrix};
use crate::error::{FeaError, Result, finite3, positive};
use crate::implicit::{ImplicitBlock, core_error};
use crate::mesh::DofMap;
use crate::node::NodeId;
use crate::shell_mesh::ShellMesh;

const EL: usize = AncfShell::NDOF;

/// The direction a node's director is tied to ([`ShellItem::attach_director`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum DirectorTarget {
    /// A fixed world vector (the director's value, not only its direction), -.
    Fixed(Vector3<f64>),
    /// A vector fixed in a rigid body, given in the body frame, -.
    Body {
        /// The body (of the system the item is added to).
        body: BodyHandle,
        /// The vector in the body frame.
        local: Vector3<f64>,
    },
}

/// A [`ShellMesh`] stepped implicitly in the system's CCP (see the module docs).
#[derive(Debug)]
pub struct ShellItem {
    name: String,
    mesh: ShellMesh,
    core: ImplicitBlock,
    /// Stiffness-proportional damping `beta`, s.
    damping: f64,
    /// Radius of the contact spheres, m (`None`: no contact).
    contact_radius: Option<f64>,
    /// Contact through the element faces (two triangles each) instead of the nodes.
    contact_faces: bool,
    contact_material: ContactMaterial,
    /// Director attachments `(node, target)`.
    directors: Vec<(usize, DirectorTarget)>,
    /// Rows of this step, 3 per director attachment (`None`: not needed).
    director_rows: Vec<Option<RowId>>,
    /// One row's coefficients on the block (`nfree`, scratch, zero between uses).
    director_coefs: Vec<f64>,
}

impl ShellItem {
    /// The item for `mesh` (supports taken now; the mesh starts at rest in its current
    /// configuration). Errors: no element, every coordinate supported.
    pub fn new(name: impl Into<String>, mesh: ShellMesh) -> Result<Self> {
        let name = name.into();
        let els = mesh.elements();
        let core = ImplicitBlock::new(
            name.clone(),
            mesh.dof_map(),
            els.len(),
            EL,
            |e, a| 6 * els[e].nodes[a / 6] + a % 6,
            |e| els[e].mass_matrix(),
        )?;
        let nfree = core.map.nfree();
        Ok(Self {
            name,
            mesh,
            core,
            damping: 0.0,
            contact_radius: None,
            contact_faces: false,
            contact_material: ContactMaterial::default(),
            directors: Vec::new(),
            director_rows: Vec::new(),
            director_coefs: vec![0.0; nfree],
        })
    }

    /// Set the stiffness-proportional damping `beta` (s, finite and >= 0; the error names
    /// `damping`): `R = beta K`. Default 0.
    pub fn set_damping(&mut self, beta: f64) -> Result<()> {
        if !(beta.is_finite() && beta >= 0.0) {
            return Err(FeaError::invalid(
                "damping",
                beta,
                "must be finite and >= 0",
            ));
        }
        self.damping = beta;
        Ok(())
    }

    /// The stiffness-proportional damping `beta`, s.
    pub fn damping(&self) -> f64 {
        self.damping
    }

    /// Attach a node's position to `target` (module docs); returns its index. Errors:
    /// unknown node, non-finite point. A body handle is checked at the step.
    pub fn attach(&mut self, node: NodeId, target: AttachTarget) -> Result<usize> {
        self.mesh.node(node)?;
        self.core.attach(node, target)
    }

    /// Tie the director of `node` to `target` (module docs; with [`attach`](Self::attach)
    /// of the same node: a clamp); returns its index. Errors: unknown node, non-finite
    /// vector. A body handle is checked at the step.
    pub fn attach_director(&mut self, node: NodeId, target: DirectorTarget) -> Result<usize> {
        self.mesh.node(node)?;
        match &target {
            DirectorTarget::Fixed(a) => finite3("director.target", a)?,
            DirectorTarget::Body { local, .. } => finite3("director.local", local)?,
        }
        self.directors.push((node.0, target));
        Ok(self.directors.len() - 1)
    }

    /// The director attachments `(node index, target)`.
    pub fn director_attachments(&self) -> &[(usize, DirectorTarget)] {
        &self.directors
    }

    /// The attachments.
    pub fn attachments(&self) -> &[Attachment] {
        &self.core.attachments
    }

    /// The force of attachment `i` on its node during the last step (`gamma / h`), N.
    pub fn reaction(&self, i: usize) -> Option<Vector3<f64>> {
        self.core.reaction(i)
    }

    /// Make every node a contact sphere of `radius` (m, finite and > 0; the error names
    /// `contact.radius`) with the surface material `material` (checked with
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

    /// Make every element's mid surface a contact surface: two triangles per element
    /// (nodes `(0, 1, 2)` and `(0, 2, 3)`), each swept by a sphere of `radius` (m, finite
    /// and > 0; `t / 2` puts the contact surface at the shell's faces), with the surface
    /// material `material`. A contact at the point `p` of a triangle acts on its three
    /// nodes with the barycentric weights of `p` (`r(p) = sum w_k r_k`: the force and
    /// the velocity use the same weights, so the virtual work is consistent). Unlike the
    /// node spheres of [`set_contact_spheres`](Self::set_contact_spheres) the surface has
    /// no gaps: a body smaller than the element cannot pass between the nodes. The
    /// triangles are flat, so a curved element's surface is cut by up to its sagitta.
    pub fn set_contact_faces(&mut self, radius: f64, material: ContactMaterial) -> Result<()> {
        self.set_contact_spheres(radius, material)?;
        self.contact_faces = true;
        Ok(())
    }

    /// The three node indices of face proxy `id` (`2 e` and `2 e + 1` of element `e`).
    fn face_nodes(&self, id: usize) -> Option<[usize; 3]> {
        let n = self.mesh.elements().get(id / 2)?.nodes;
        Some(if id.is_multiple_of(2) {
            [n[0], n[1], n[2]]
        } else {
            [n[0], n[2], n[3]]
        })
    }

    /// Radius of the contact spheres, m (`None`: contact off).
    pub fn contact_radius(&self) -> Option<f64> {
        self.contact_radius
    }

    /// The mesh (current configuration).
    pub fn mesh(&self) -> &ShellMesh {
        &self.mesh
    }

    /// Set the follower pressure on every element, Pa (see [`ShellMesh::set_pressure`]).
    pub fn set_pressure(&mut self, pressure: f64) -> Result<()> {
        self.mesh.set_pressure(pressure)
    }

    /// The numbering of the free coordinates (the dof of the item's block).
    pub fn dof_map(&self) -> &DofMap {
        &self.core.map
    }

    /// Velocity of node `n`: `(r_dot, d_dot)`, m/s and 1/s.
    pub fn node_velocity(&self, n: NodeId) -> Result<(Vector3<f64>, Vector3<f64>)> {
        self.mesh.node(n)?;
        let v = &self.core.velocity[6 * n.0..6 * n.0 + 6];
        Ok((
            Vector3::new(v[0], v[1], v[2]),
            Vector3::new(v[3], v[4], v[5]),
        ))
    }

    /// Set the velocity of node `n` (m/s) and the rate of its director (1/s); components
    /// on supported coordinates must be 0 (the error names the node and component).
    pub fn set_node_velocity(
        &mut self,
        n: NodeId,
        velocity: Vector3<f64>,
        director_rate: Vector3<f64>,
    ) -> Result<()> {
        self.mesh.node(n)?;
        finite3("node.velocity", &velocity)?;
        finite3("node.director_rate", &director_rate)?;
        let v = [
            velocity.x,
            velocity.y,
            velocity.z,
            director_rate.x,
            director_rate.y,
            director_rate.z,
        ];
        self.core
            .set_velocity(6 * n.0, &v, &format!("node {} velocity", n.0))
    }

    /// Set the configuration (all coordinates, [`ShellMesh::set_coordinates`]); the
    /// velocities are kept.
    pub fn set_coordinates(&mut self, q: &[f64]) -> Result<()> {
        self.mesh.set_coordinates(q)
    }

    /// Kinetic energy `v' M v / 2` (consistent mass), J.
    pub fn kinetic_energy(&self) -> f64 {
        self.core.kinetic_energy()
    }

    /// Linear momentum `sum M v` over the position rows, kg m/s (the director rows carry
    /// no translation).
    pub fn linear_momentum(&self) -> Vector3<f64> {
        self.core.momentum(|g| (g % 6 < 3).then_some(g % 6))
    }

    /// Angular momentum about the origin, `sum_n r_n x p_r,n + d_n x p_d,n` with
    /// `p = M v` (consistent mass; the director's momentum carries the `z^2` moment of
    /// the thickness), kg m^2/s: conserved with that of the bodies when no external
    /// torque acts (the follower pressure of a closed volume is internal).
    pub fn angular_momentum(&self) -> Vector3<f64> {
        self.core.angular_momentum()
    }

    /// Strain energy of the current configuration, J.
    pub fn strain_energy(&self) -> f64 {
        self.mesh.strain_energy()
    }

    /// Potential of gravity `g` (m/s^2): `-sum_e F_g,e . e_e` (the consistent load is
    /// constant, so this is exact), J.
    pub fn gravity_potential(&self, gravity: &Vector3<f64>) -> f64 {
        let q = self.mesh.coordinates();
        -self
            .mesh
            .elements()
            .iter()
            .map(|el| {
                el.gravity_force(gravity)
                    .dot(&ShellMesh::element_coordinates(el, &q))
            })
            .sum::<f64>()
    }
}

impl PhysicsItem for ShellItem {
    fn name(&self) -> &str {
        &self.name
    }

    /// Assemble `F_ext + F_g + F_p - Q` and `H = M + (h^2 + h beta) K - h^2 sym(K_p)` at
    /// `q(l)`, refactorize.
    fn begin_step(&mut self, ctx: &StepContext) -> CoreResult<()> {
        let h = ctx.h;
        let core = &mut self.core;
        for (n, node) in self.mesh.nodes().iter().enumerate() {
            core.q[6 * n..6 * n + 3].copy_from_slice(node.position.as_slice());
            core.q[6 * n + 3..6 * n + 6].copy_from_slice(node.slope.as_slice());
            core.force[6 * n..6 * n + 3].copy_from_slice(node.force.as_slice());
            core.force[6 * n + 3..6 * n + 6].fill(0.0);
        }
        core.begin_assembly();
        let c = h * h + h * self.damping;
        for (e, el) in self.mesh.elements().iter().enumerate() {
            let x = ShellMesh::element_coordinates(el, &core.q);
            let (qe, ke) = el.force_and_tangent(&x, true);
            let mut fe = el.gravity_force(&ctx.gravity) - qe;
            core.add_element_matrix(e, &ke, c);
            let p = self.mesh.element_pressure(e).unwrap_or(0.0);
            if p != 0.0 {
                let (fp, kp) = el.pressure_force(&x, p, true);
                fe += fp;
                let sym: ShellMatrix = 0.5 * (kp + kp.transpose());
                core.add_element_matrix(e, &sym, -h * h);
            }
            for a in 0..EL {
                core.force[6 * el.nodes[a / 6] + a % 6] += fe[a];
            }
        }
        core.finish_assembly(ctx, 6)
    }

    fn add_variables(&mut self, vars: &mut Variables) {
        self.core.add_variables(vars);
    }

    /// `k = M v + h (F_ext + F_g + F_p - Q)` on the free coordinates.
    fn load_momentum(&self, ctx: &StepContext, vars: &Variables, k: &mut [f64]) {
        self.core.load_momentum(ctx, vars, k);
    }

    /// One sphere per node (id = node index) when contact is on.
    fn collision_proxies(&self, out: &mut Vec<CollisionProxy>) {
        let Some(radius) = self.contact_radius else {
            return;
        };
        if self.contact_faces {
            let nodes = self.mesh.nodes();
            for id in 0..2 * self.mesh.elements().len() {
                if let Some(f) = self.face_nodes(id) {
                    out.push(CollisionProxy {
                        shape: ProxyShape::Triangle {
                            vertices: f.map(|k| nodes[k].position),
                            thickness: radius,
                        },
                        material: self.contact_material,
                        id: id as u32,
                    });
                }
            }
            return;
        }
        for (n, node) in self.mesh.nodes().iter().enumerate() {
            out.push(CollisionProxy {
                shape: ProxyShape::Sphere {
                    center: node.position,
                    radius,
                },
                material: self.contact_material,
                id: n as u32,
            });
        }
    }

    /// `d . r_dot` of the node: `d` on its free position coordinates. No known velocity.
    fn proxy_jacobian(
        &self,
        proxy: u32,
        p: &Vector3<f64>,
        dirs: &[Vector3<f64>; 3],
        entry: &mut dyn FnMut(BlockId, [&[f64]; 3]),
    ) -> [f64; 3] {
        if self.contact_faces {
            if let Some(f) = self.face_nodes(proxy as usize) {
                let nodes = self.mesh.nodes();
                let w = barycentric(f.map(|k| nodes[k].position), p);
                let weights = [(6 * f[0], w[0]), (6 * f[1], w[1]), (6 * f[2], w[2])];
                self.core.point_jacobian(&weights, dirs, entry);
            }
            return [0.0; 3];
        }
        let node = proxy as usize;
        if node < self.mesh.nodes().len() {
            self.core.point_jacobian(&[(6 * node, 1.0)], dirs, entry);
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
        let mesh = &self.mesh;
        self.core.attachment_rows(ctx, bodies, rows, 6, |n| {
            Ok(mesh.node(NodeId(n)).map_err(core_error)?.position)
        })?;
        self.director_rows.clear();
        let Some(block) = self.core.block else {
            return Ok(());
        };
        let nodes = mesh.nodes();
        let map = &self.core.map;
        push_director_rows(
            &self.directors,
            |n| nodes[n].slope,
            |n, c| map.free_index(6 * n + 3 + c),
            &AttachContext {
                block,
                bodies,
                h: ctx.h,
                label: &self.core.label,
            },
            &mut self.director_coefs,
            rows,
            &mut self.director_rows,
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
        if self.core.advance(ctx, vars, v, problem, gamma, 6)? {
            self.mesh
                .set_coordinates(&self.core.q)
                .map_err(core_error)?;
        }
        Ok(())
    }
}

/// Barycentric weights of the point of triangle `t` nearest to `p` (the weights of the
/// plane projection, clamped to the triangle and renormalized; a degenerate triangle gives
/// equal weights).
fn barycentric(t: [Vector3<f64>; 3], p: &Vector3<f64>) -> [f64; 3] {
    let (e1, e2, d) = (t[1] - t[0], t[2] - t[0], p - t[0]);
    let (a, b, c) = (e1.dot(&e1), e1.dot(&e2), e2.dot(&e2));
    let (r1, r2) = (d.dot(&e1), d.dot(&e2));
    let det = a * c - b * b;
    if det <= 1e-300 || !det.is_finite() {
        return [1.0 / 3.0; 3];
    }
    let u = (c * r1 - b * r2) / det;
    let v = (a * r2 - b * r1) / det;
    let w = [(1.0 - u - v).max(0.0), u.max(0.0), v.max(0.0)];
    let sum = w[0] + w[1] + w[2];
    [w[0] / sum, w[1] / sum, w[2] / sum]
}
