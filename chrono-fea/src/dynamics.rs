//! A cable mesh as a [`PhysicsItem`]: implicit dynamics in the system's CCP.
//!
//! # The step
//!
//! Linearized implicit (backward) Euler, one Newton step of
//! `M (v+ - v) = h f(q+, v+) + D gamma`, `q+ = q + h v+`, with
//! `f(q, v) = F_ext(q) - Q(q) - R v` (applied loads and gravity, the elastic force
//! `Q = dU/dq` of the elements, Rayleigh damping `R = beta K`), linearized about
//! `(q, v)` with the tangent `K = dQ/dq` (closed form, [`AncfCable::force_and_tangent`]):
//!
//! ```text
//! (M + h R + h^2 K) v+ = M v + h (F_ext - Q(q)) + D gamma
//! ```
//!
//! (the `h R v` on both sides cancels). This is the form of every block of the NSC step,
//! `H v+ = k + D gamma`, with `H = M + h R + h^2 K` as the block's coupled mass operator
//! ([`SparseSpd`](crate::SparseSpd), faer sparse Cholesky, symbolic analysis once,
//! numeric refactorization every step in [`begin_step`](PhysicsItem::begin_step)), `k` from
//! [`load_momentum`](PhysicsItem::load_momentum). The solver finds `gamma` for the rows of
//! joints, contacts and this mesh's attachments together; [`update`](PhysicsItem::update)
//! sets `q+ = q + h v+`. Anitescu & Tasora's stepper with a stiff item, as Chrono's
//! `ChTimestepperEulerImplicitLinearized` (factors `M: 1, dF/dv: -h, dF/dq: -h^2`).
//!
//! # Numerical damping
//!
//! For a linear mode of frequency `omega` the step is exactly backward Euler: the
//! amplitude shrinks by `1 / sqrt(1 + (omega h)^2)` per step, so the energy of the mode
//! decays as `exp(-omega^2 h t)` for `omega h << 1` and high modes (`omega h >> 1`, the
//! axial waves of a slender beam) are removed within a few steps; the period lengthens by
//! a relative `(omega h)^2 / 3`. Measured figures are in `docs/validation-fea.md`.
//!
//! # Supports and attachments
//!
//! Supports of the mesh ([`CableMesh::fix_position`], [`CableMesh::clamp`] ...) remove
//! coordinates, as in statics: the block has the free coordinates only. An
//! [`Attachment`] ties a node's position to a fixed world point or to a point of a rigid
//! body with three bilateral rows `d . (r_node - p) = 0` (`d` the world axes), stabilized
//! like the joints: `b = d . (r_node - p) / h` (minus the known velocity of a kinematic
//! body's point). The slope stays free: a pin (spherical joint) for the cable element,
//! which has no torsion. [`CableItem::attach_slope`] keeps the slope along a fixed
//! direction or a direction of a rigid body as well (two more rows, module
//! [`slope_attach`](crate::slope_attach)): with both, the node is clamped to the body.
//!
//! # Contact
//!
//! The item exposes its nodes (and, optionally, its element midpoints) to the body
//! colliders as spheres of radius [`CableItem::contact_radius`]
//! ([`collision_proxies`](PhysicsItem::collision_proxies)); the system turns their
//! contacts into ordinary friction-cone rows (Anitescu & Tasora) in the same CCP as the
//! attachments. The item's side of a row along a direction `d` is `d . r_dot(p)`, with
//! `r(xi) = S1 r_A + S2 r_x,A + S3 r_B + S4 r_x,B` (the element's Hermite interpolation):
//! coefficient `d` on a node's position for a node sphere, and `S_k(1/2) d` on the four
//! position and slope blocks for a midpoint sphere, restricted to the free coordinates of
//! the coupled block (a supported coordinate does not move and contributes nothing).
//! The proxies are at the positions of the start of the step, as the body colliders.

use chrono_core::body::BodyHandle;
use chrono_core::collision::{CollisionProxy, ProxyShape};
use chrono_core::descriptor::{BlockId, CcpProblem, ConstraintRows, Variables};
use chrono_core::item::{PhysicsItem, StepContext};
use chrono_core::{ContactMaterial, Result as CoreResult};
use nalgebra::Vector3;

use crate::attach_rows::AttachContext;
use crate::element::cable::hermite;
use crate::element::{AncfCable, ElementVector};
use crate::error::{FeaError, Result, finite3, positive};
use crate::implicit::{ImplicitBlock, core_error};
use crate::mesh::{CableMesh, DofMap};
use crate::node::NodeId;
use crate::slope_attach::{SlopeAttachment, SlopeRows, SlopeTarget};

/// What a node is attached to.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum AttachTarget {
    /// A fixed world point, m.
    Point(Vector3<f64>),
    /// A point of a rigid body given in the body frame (m, relative to its center of mass).
    Body {
        /// The body (of the system the item is added to).
        body: BodyHandle,
        /// The point in the body frame, m.
        local: Vector3<f64>,
    },
}

/// A node's position tied to a target by three bilateral rows (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Attachment {
    /// The node.
    pub node: NodeId,
    /// What it is attached to.
    pub target: AttachTarget,
}

const EL: usize = AncfCable::NDOF;

/// A [`CableMesh`] stepped implicitly in the system's CCP (see the module docs).
#[derive(Debug)]
pub struct CableItem {
    name: String,
    mesh: CableMesh,
    core: ImplicitBlock,
    /// Radius of the contact spheres, m.
    contact_radius: f64,
    /// Surface material of the contact spheres.
    contact_material: ContactMaterial,
    /// Whether the item exposes any contact sphere.
    contact_enabled: bool,
    /// Whether element midpoints carry a sphere too.
    midpoint_contacts: bool,
    /// Slope attachments and their rows.
    slopes: SlopeRows,
}

impl CableItem {
    /// The item for `mesh` (its supports are taken now; the mesh starts at rest). Errors:
    /// no element, every coordinate supported.
    pub fn new(name: impl Into<String>, mesh: CableMesh) -> Result<Self> {
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
        let contact_radius = default_contact_radius(&mesh);
        Ok(Self {
            name,
            mesh,
            core,
            contact_radius,
            contact_material: ContactMaterial::default(),
            contact_enabled: true,
            midpoint_contacts: false,
            slopes: SlopeRows::default(),
        })
    }

    /// Radius of the contact spheres, m. Default: the largest over the elements of
    /// `sqrt(3 I / A)`, half the height of the rectangular section with the same area and
    /// second moment (`A = w t`, `I = w t^3 / 12`, so `t / 2 = sqrt(3 I / A)`).
    pub fn contact_radius(&self) -> f64 {
        self.contact_radius
    }

    /// Set the radius of the contact spheres (m, finite and > 0; the error names
    /// `contact.radius`).
    pub fn set_contact_radius(&mut self, radius: f64) -> Result<()> {
        self.contact_radius = positive("contact.radius", radius)?;
        Ok(())
    }

    /// Surface material of the contact spheres (combined with the collider's by the
    /// system). Default: [`ContactMaterial::default`].
    pub fn contact_material(&self) -> &ContactMaterial {
        &self.contact_material
    }

    /// Set the surface material of the contact spheres; checked with
    /// [`ContactMaterial::validate`] (the error names the field and value).
    pub fn set_contact_material(&mut self, material: ContactMaterial) -> Result<()> {
        material.validate().map_err(|e| {
            FeaError::invalid("contact.material", e.to_string(), "rejected by chrono-core")
        })?;
        self.contact_material = material;
        Ok(())
    }

    /// Turn the contact spheres on or off (default on).
    pub fn set_contact_enabled(&mut self, enabled: bool) {
        self.contact_enabled = enabled;
    }

    /// Also put a sphere at each element's midpoint `r(1/2)` (default off), so that a
    /// coarse mesh lying on an edge or a corner does not sag through it between nodes.
    /// Proxy ids: nodes `0..n_nodes`, then element `e` as `n_nodes + e`.
    pub fn set_midpoint_contacts(&mut self, on: bool) {
        self.midpoint_contacts = on;
    }

    /// The Hermite weights of proxy `proxy` on the global coordinates: up to four
    /// `(first global coordinate of a 3-block, weight)` pairs (`None`: unknown id).
    fn proxy_weights(&self, proxy: u32) -> Option<[(usize, f64); 4]> {
        let nn = self.mesh.nodes().len();
        let p = proxy as usize;
        if p < nn {
            return Some([(6 * p, 1.0), (0, 0.0), (0, 0.0), (0, 0.0)]);
        }
        let el = self.mesh.elements().get(p - nn)?;
        let s = hermite(0.5, el.length()).0;
        let [a, b] = el.nodes;
        Some([
            (6 * a, s[0]),
            (6 * a + 3, s[1]),
            (6 * b, s[2]),
            (6 * b + 3, s[3]),
        ])
    }

    /// The mesh (current configuration).
    pub fn mesh(&self) -> &CableMesh {
        &self.mesh
    }

    /// The numbering of the free coordinates (the dof of the item's block).
    pub fn dof_map(&self) -> &DofMap {
        &self.core.map
    }

    /// Attach a node's position to `target` (see [`Attachment`]); returns its index.
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

    /// Keep the slope `r_x` of `node` along `target` (two bilateral rows, module
    /// [`slope_attach`](crate::slope_attach)); with [`attach`](Self::attach) of the same
    /// node to the same body, a clamp. Returns its index. Errors: unknown node, zero or
    /// non-finite direction. A body handle is checked at the step.
    pub fn attach_slope(&mut self, node: NodeId, target: SlopeTarget) -> Result<usize> {
        self.mesh.node(node)?;
        Ok(self.slopes.push(SlopeAttachment::new(node, target)?))
    }

    /// The slope attachments.
    pub fn slope_attachments(&self) -> &[SlopeAttachment] {
        &self.slopes.attachments
    }

    /// The couple of slope attachment `i` on its node's section during the last step
    /// (world, N m; the body receives its opposite): `s x sum_k e_k gamma_k / h`.
    pub fn slope_reaction(&self, i: usize) -> Option<Vector3<f64>> {
        self.slopes.couple(i)
    }

    /// Velocity of node `n`: `(r_dot, r_x_dot)`, m/s and 1/s.
    pub fn node_velocity(&self, n: NodeId) -> Result<(Vector3<f64>, Vector3<f64>)> {
        self.mesh.node(n)?;
        let v = &self.core.velocity[6 * n.0..6 * n.0 + 6];
        Ok((
            Vector3::new(v[0], v[1], v[2]),
            Vector3::new(v[3], v[4], v[5]),
        ))
    }

    /// Set the velocity of node `n` (m/s) and the rate of its slope (1/s); components on
    /// supported coordinates must be 0.
    pub fn set_node_velocity(
        &mut self,
        n: NodeId,
        velocity: Vector3<f64>,
        slope_rate: Vector3<f64>,
    ) -> Result<()> {
        self.mesh.node(n)?;
        finite3("node.velocity", &velocity)?;
        finite3("node.slope_rate", &slope_rate)?;
        let v = [
            velocity.x,
            velocity.y,
            velocity.z,
            slope_rate.x,
            slope_rate.y,
            slope_rate.z,
        ];
        self.core
            .set_velocity(6 * n.0, &v, &format!("node {} velocity", n.0))
    }

    /// Set the applied generalized load on the nodal coordinates (6 per node; N on the
    /// positions, N m on the slopes; see [`CableMesh::set_coordinate_load`]): it enters
    /// `F_ext` from the next step on, until changed.
    pub fn set_coordinate_load(&mut self, load: &[f64]) -> Result<()> {
        self.mesh.set_coordinate_load(load)
    }

    /// Set the configuration (all coordinates, [`CableMesh::set_coordinates`]); the
    /// velocities are kept.
    pub fn set_coordinates(&mut self, q: &[f64]) -> Result<()> {
        self.mesh.set_coordinates(q)
    }

    /// Kinetic energy `v' M v / 2` (consistent mass), J.
    pub fn kinetic_energy(&self) -> f64 {
        self.core.kinetic_energy()
    }

    /// Strain energy of the current configuration, J.
    pub fn strain_energy(&self) -> f64 {
        self.mesh.strain_energy()
    }

    /// Potential of gravity `g` (m/s^2): `-sum_e Q_g,e . e_e = -∫ rho A g . r dx`, exact
    /// for the cubic interpolation, J.
    pub fn gravity_potential(&self, gravity: &Vector3<f64>) -> f64 {
        let q = self.mesh.coordinates();
        -self
            .mesh
            .elements()
            .iter()
            .map(|el| {
                el.gravity_force(gravity)
                    .dot(&self.mesh.element_coordinates(el, &q))
            })
            .sum::<f64>()
    }
}

/// `max_e sqrt(3 I_e / A_e)` (see [`CableItem::contact_radius`]), m.
fn default_contact_radius(mesh: &CableMesh) -> f64 {
    mesh.elements()
        .iter()
        .map(|el| (3.0 * el.material().second_moment / el.material().area).sqrt())
        .fold(0.0, f64::max)
}

impl PhysicsItem for CableItem {
    fn name(&self) -> &str {
        &self.name
    }

    /// Assemble `F_ext - Q(q)` and `H = M + (h^2 + h beta) K` at `q(l)`, refactorize `H`.
    fn begin_step(&mut self, ctx: &StepContext) -> CoreResult<()> {
        let h = ctx.h;
        let core = &mut self.core;
        for (n, node) in self.mesh.nodes().iter().enumerate() {
            core.q[6 * n..6 * n + 3].copy_from_slice(node.position.as_slice());
            core.q[6 * n + 3..6 * n + 6].copy_from_slice(node.slope.as_slice());
            core.force[6 * n..6 * n + 3].copy_from_slice(node.force.as_slice());
            core.force[6 * n + 3..6 * n + 6].fill(0.0);
        }
        for (f, l) in core.force.iter_mut().zip(self.mesh.coordinate_load()) {
            *f += l;
        }
        core.begin_assembly();
        for (e, el) in self.mesh.elements().iter().enumerate() {
            let ee: ElementVector = self.mesh.element_coordinates(el, &core.q);
            let (qe, ke) = el.force_and_tangent(&ee, true);
            let qg = el.gravity_force(&ctx.gravity);
            core.add_element_matrix(e, &ke, h * h + h * el.material().damping);
            for a in 0..EL {
                core.force[6 * el.nodes[a / 6] + a % 6] += qg[a] - qe[a];
            }
        }
        core.finish_assembly(ctx, 6)
    }

    fn add_variables(&mut self, vars: &mut Variables) {
        self.core.add_variables(vars);
    }

    /// `k = M v + h (F_ext - Q(q))` on the free coordinates.
    fn load_momentum(&self, ctx: &StepContext, vars: &Variables, k: &mut [f64]) {
        self.core.load_momentum(ctx, vars, k);
    }

    /// One sphere per node at `r` (id = node index), and with
    /// [`set_midpoint_contacts`](CableItem::set_midpoint_contacts) one per element at
    /// `r(1/2)` (id = `n_nodes + e`), radius [`contact_radius`](CableItem::contact_radius).
    fn collision_proxies(&self, out: &mut Vec<CollisionProxy>) {
        if !self.contact_enabled {
            return;
        }
        let nodes = self.mesh.nodes();
        let sphere = |center, id| CollisionProxy {
            shape: ProxyShape::Sphere {
                center,
                radius: self.contact_radius,
            },
            material: self.contact_material,
            id,
        };
        for (i, node) in nodes.iter().enumerate() {
            out.push(sphere(node.position, i as u32));
        }
        if self.midpoint_contacts {
            for e in 0..self.mesh.elements().len() {
                let id = (nodes.len() + e) as u32;
                let Some(w) = self.proxy_weights(id) else {
                    continue;
                };
                // The 3-blocks are positions (even) or slopes (odd) of the two nodes.
                let c = w.iter().fold(Vector3::zeros(), |acc, &(g, s)| {
                    let node = &nodes[g / 6];
                    acc + s * if g % 6 == 0 {
                        node.position
                    } else {
                        node.slope
                    }
                });
                out.push(sphere(c, id));
            }
        }
    }

    /// `d . r_dot` of the proxy's centre: `S_k d` on the free coordinates of the four
    /// 3-blocks (a node sphere: `d` on its position). The whole sphere translates with its
    /// centre (the cable has no section rotation), so `p` is not needed. No known
    /// velocity: a supported coordinate is at rest.
    fn proxy_jacobian(
        &self,
        proxy: u32,
        _p: &Vector3<f64>,
        dirs: &[Vector3<f64>; 3],
        entry: &mut dyn FnMut(BlockId, [&[f64]; 3]),
    ) -> [f64; 3] {
        if let Some(w) = self.proxy_weights(proxy) {
            self.core.point_jacobian(&w, dirs, entry);
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
        let Some(block) = self.core.block else {
            return Ok(());
        };
        let (nodes, map) = (mesh.nodes(), &self.core.map);
        self.slopes.push_rows(
            |n| nodes[n].slope,
            |n, c| map.free_index(6 * n + 3 + c),
            map.nfree(),
            &AttachContext {
                block,
                bodies,
                h: ctx.h,
                label: &self.core.label,
            },
            rows,
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
            self.slopes.record(problem, gamma, ctx.h);
            self.mesh
                .set_coordinates(&self.core.q)
                .map_err(core_error)?;
        }
        Ok(())
    }
}
