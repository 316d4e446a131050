//! The [`ConstraintFluid`] physics item.

use chrono_core::Bodies;
use chrono_core::body::{BodyHandle, RigidBody};
use chrono_core::collision::{CollisionProxy, ProxyShape};
use chrono_core::descriptor::{
    BlockId, CcpProblem, ConstraintRows, MassOperator, RowEntry, RowId, Variables,
};
use chrono_core::error::{ChronoError, Result};
use chrono_core::item::{PhysicsItem, StepContext};
use chrono_core::material::ContactMaterial;
use chrono_core::math::{Point3, Vector3};
use chrono_core::particles::{CellGrid, GridConfig, Kernel, NeighborList};

use chrono_core::density_rows::{DensityField, RowBuf, compliance};

use crate::density::FluidField;
use crate::geometry::lattice_mass;
use crate::settings::CfluidSettings;
use chrono_core::density_rows::SupportModel;

mod access;
mod density_projection;
mod output;
mod projection;
mod push;

use push::PushRow;

pub use density_projection::ProjectionReport;

pub use output::{KIND_BODY_MARKER, KIND_FLUID, KIND_WALL};

/// A constraint fluid (H. Mazhar, "Parallel multi-body dynamics with frictional contact
/// and constraint fluids", PhD thesis, UW-Madison 2016; the seed's "Alternative Approach:
/// Constrained Fluids"): fluid particles are 3-dof point masses of the system's CCP, and
/// incompressibility is one holonomic constraint per particle,
///
/// ```text
/// C_i(x) = rho_i / rho_0 - 1,     rho_i = m_k W(0) + sum_j m_k W(|x_i - x_j|)
/// ```
///
/// (SPH summation over fluid particles and wall markers with a chrono-core kernel, the
/// neighbours from the chrono-core cell grid), enforced at the velocity level with the
/// stabilization `C_i / h`.
///
/// **Two masses.** A particle stands for one lattice cell of fluid: its inertial and
/// gravitational mass is `m = rho_0 dp^3` ([`particle_mass`](Self::particle_mass)). The
/// density sum uses the kernel mass `m_k = rho_0 / sum_lattice W`
/// ([`kernel_mass`](Self::kernel_mass), [`lattice_mass`]), so that the initial cubic
/// lattice sums to exactly `rho_0` (`C_i = 0` at the start): the rows hold the kernel
/// number density of the lattice. With one mass for both (`m = m_k`), the lattice fluid
/// held `C_i = 0` at a true mass density `n m = rho_0 / (dp^3 sum_lattice W)`, 1.7 % light
/// for Wendland C2 at `h_k = 1.2 dp` (`dp^3 sum_lattice W = 1.0175`), and a floating body
/// sat 1.7 % too deep (`cfluid-floating-box`, `docs/validation-cfluid.md`).
///
/// Each particle contributes one row, written with
/// `D_i = -grad C_i` (1/m; entries `(m_k/rho_0) grad W_ij`, see the `density` module) so that
/// its multiplier `g_i` (N m s) is a pressure impulse, positive when it pushes:
///
/// ```text
/// c_i = D_i' v + b_i + eps_i g_i,   b_i = -min(C_i / h, max_recovery_rate),
/// eps_i = kappa rho_0 / (h^2 m)
/// ```
///
/// bilateral (`c_i = 0`) or unilateral (`0 <= g_i ⊥ c_i >= 0`) according to
/// [`SurfaceMode`](crate::SurfaceMode). After a solve, `C_i(t + h) ~ kappa p_i m_k / m`
/// (the compliance makes the fluid as compressible as one of bulk modulus `1 / kappa`),
/// and the pressure is
/// `p_i = g_i rho_0 / (h m_k)` (Pa; [`pressure`](Self::pressure)): the force on particle
/// `j` is `-sum_i (g_i / h) grad_j C_i`, which with `g_i / h = p_i m_k / rho_0` is the
/// symmetric SPH pressure force `-m_k sum_i m_k (p_i + p_j) / rho_0^2 grad W`.
///
/// **Viscosity** is an XSPH velocity smoothing applied after the solve (Monaghan 1989):
/// `v_i <- v_i + eps sum_j (2 m_k / (rho_i + rho_j)) (v_j - v_i) W_ij` over fluid
/// neighbours, then `x <- x + h v` with the smoothed velocity (symplectic Euler). It damps
/// the relative motion of neighbours (an artificial viscosity of order
/// `eps h_k^2 / h`), conserves momentum (the pair weights are symmetric), and perturbs
/// the constraint velocities by `O(eps)`, which the next step's stabilization removes.
///
/// **Walls** are fixed marker particles (no variables) that enter the density sum and
/// the self term of the Jacobian: a fluid particle cannot compress against a wall, and
/// the wall needs no contact rows. Use at least [`wall_layers`](crate::wall_layers)
/// layers so the support is full.
///
/// **Bodies.** Two couplings to rigid bodies, both rows of the same CCP (so the momentum
/// the fluid gives a body is exactly the momentum the body gives the fluid):
///
/// - *contact*: each particle is a collision proxy, a sphere of radius
///   `contact_radius_over_dp * dp` with friction `contact_friction`
///   ([`CfluidSettings::body_contacts`]); the system builds friction-cone rows between it
///   and any body collider, the particle's side being its own block along the contact
///   directions ([`PhysicsItem::proxy_jacobian`]). This keeps particles out of a body
///   whatever happens, but alone it gets the pressure on a body wrong: a particle next to
///   the body misses the neighbours the body would have had, its density has a deficit,
///   its row is slack, and the near-body layers can pack until the deficit is gone, so
///   a floating body sinks by a fraction of `dp` too deep.
/// - *markers* ([`attach_body`](Self::attach_body)): marker points fixed in a body's
///   frame (BCE-like, e.g. [`box_markers`](crate::box_markers)) enter the density sum like
///   the wall markers, at `x_k = x_b + R r_k` at the start of each step, so the fluid next
///   to the body has a full kernel support and its rows hold `rho_0` up to the body face;
///   each density row then also has a 6-entry block on the body (`sum_k c_k` and
///   `sum_k (x_k - x_b) x c_k`, see the `density` module), through which the row's pressure
///   impulse pushes the body: buoyancy comes out of the same multipliers as the fluid's
///   own pressure. Fixed and kinematic bodies have no block: their markers' known
///   velocity goes into the right-hand side. With markers attached, the rows are built in
///   [`PhysicsItem::add_body_constraints`] (which sees the bodies' poses).
///   With [`CfluidSettings::body_marker_rows`] (the default) each marker with fluid
///   neighbours also gets a density row of its own, always unilateral (a pressure on
///   the body side of the face, which also keeps the fluid from packing against it).
///
/// **Warm start**: the last impulses times
/// [`warm_start_factor`](CfluidSettings::warm_start_factor), by particle, through
/// [`PhysicsItem::warm_start`].
///
/// Allocation: after the first step, a step allocates nothing unless the neighbour
/// counts grow (the grid, the neighbour list, the per-row buffers and the row-entry
/// scratch are kept). Density, rows and XSPH are rayon-parallel over particles.
pub struct ConstraintFluid {
    name: String,
    settings: CfluidSettings,
    kernel: Kernel,
    /// Inertial and gravitational mass of a particle, `rho_0 dp^3`, kg.
    mass: f64,
    /// Mass in the density sums, `rho_0 / sum_lattice W` ([`lattice_mass`]), kg.
    kernel_mass: f64,
    mass_op: MassOperator,
    n_fluid: usize,
    /// Positions of fluid particles then wall markers (structure of arrays), m.
    pos: [Vec<f64>; 3],
    vel: Vec<[f64; 3]>,
    rho: Vec<f64>,
    /// Support fractions `phi_i` of the last step (1 without
    /// [`CfluidSettings::surface_reference`]).
    phi: Vec<f64>,
    /// The planar-surface model of the lattice, with `surface_reference`.
    support_model: Option<SupportModel>,
    gamma: Vec<f64>,
    row_ids: Vec<RowId>,
    first_block: Option<BlockId>,
    grid: CellGrid,
    nbrs: NeighborList,
    rows: Vec<RowBuf>,
    entries: Vec<RowEntry<'static>>,
    vel_scratch: Vec<[f64; 3]>,
    /// Position projection scratch (densities, multipliers) and its last outcome.
    proj_rho: Vec<f64>,
    proj_lambda: Vec<f64>,
    projection: (u32, f64),
    /// The density projection (`CfluidSettings::density_projection`): solver and scratch.
    dproj: density_projection::DensityProjection,
    last_h: f64,
    neighbors_fresh: bool,
    /// Number of fluid particles and wall markers (body markers follow).
    n_static: usize,
    /// Attached bodies: handle and first marker (index into `marker_local`).
    bodies: Vec<(BodyHandle, usize)>,
    /// Body markers in their body's frame, m.
    marker_local: Vec<Vector3<f64>>,
    /// Body slot of each body marker.
    marker_owner: Vec<u32>,
    /// Each slot's body position at the step, m.
    body_origin: Vec<[f64; 3]>,
    /// Row buffers, densities (kg/m^3) and impulses (N s) of the body markers.
    marker_rows: Vec<RowBuf>,
    marker_rho: Vec<f64>,
    marker_gamma: Vec<f64>,
    /// The body markers that have a row this step, and the row.
    marker_row_ids: Vec<(u32, RowId)>,
    /// Row buffers, densities (kg/m^3), impulses (N s) of the wall markers, and the wall
    /// markers that have a row this step ([`CfluidSettings::wall_marker_rows`]).
    wall_rows: Vec<RowBuf>,
    wall_rho: Vec<f64>,
    wall_gamma: Vec<f64>,
    wall_row_ids: Vec<(u32, RowId)>,
    /// Velocity relaxation rate after each solve, 1/s ([`ConstraintFluid::set_damping`]).
    damping: f64,
}

/// Re-types an empty vector of row entries for another borrow: the allocation is kept
/// (in-place collect of a same-layout type), so the scratch survives across steps
/// without borrowing the item.
fn recycle<'b>(mut v: Vec<RowEntry<'_>>) -> Vec<RowEntry<'b>> {
    v.clear();
    v.into_iter().map(|_| unreachable!()).collect()
}

fn check_points(field: &str, pts: &[[f64; 3]]) -> Result<()> {
    for (i, p) in pts.iter().enumerate() {
        for a in 0..3 {
            if !p[a].is_finite() {
                return Err(ChronoError::invalid(
                    format!("{field}[{i}][{a}]"),
                    p[a],
                    "must be finite",
                ));
            }
        }
    }
    Ok(())
}

impl ConstraintFluid {
    /// A fluid of particles at `fluid` (at rest) in walls of markers at `walls`, m. The
    /// particle mass is `rho_0 dp^3`, the kernel mass [`lattice_mass`] (the lattice of
    /// `settings.spacing` sums to `rho_0`; see the type's documentation). Errors name
    /// the bad field: settings, an empty fluid, a non-finite position.
    pub fn new(
        name: impl Into<String>,
        settings: CfluidSettings,
        fluid: &[[f64; 3]],
        walls: &[[f64; 3]],
    ) -> Result<Self> {
        settings.validate()?;
        if fluid.is_empty() {
            return Err(ChronoError::invalid(
                "fluid",
                0,
                "a constraint fluid needs at least one particle",
            ));
        }
        check_points("fluid", fluid)?;
        check_points("walls", walls)?;
        let kernel = Kernel::new(settings.kernel, settings.smoothing_length(), 3)?;
        let kernel_mass = lattice_mass(&kernel, settings.spacing, settings.rest_density);
        let mass = settings.rest_density * settings.spacing.powi(3);
        let mass_op = MassOperator::particle(mass)?;
        let config = GridConfig::bounded(
            kernel.support(),
            settings.domain_lower,
            settings.domain_upper,
        )
        .with_periodic(settings.periodic);
        let grid = CellGrid::new(config)?;
        let n_fluid = fluid.len();
        let pos = std::array::from_fn(|a| fluid.iter().chain(walls).map(|p| p[a]).collect());
        Ok(Self {
            name: name.into(),
            kernel,
            mass,
            kernel_mass,
            mass_op,
            n_fluid,
            pos,
            vel: vec![[0.0; 3]; n_fluid],
            rho: vec![settings.rest_density; n_fluid],
            phi: vec![1.0; n_fluid],
            support_model: settings
                .surface_reference
                .then(|| SupportModel::new(&kernel, settings.spacing)),
            gamma: vec![0.0; n_fluid],
            row_ids: Vec::with_capacity(n_fluid),
            first_block: None,
            grid,
            nbrs: NeighborList::new(),
            rows: vec![RowBuf::default(); n_fluid],
            entries: Vec::new(),
            vel_scratch: vec![[0.0; 3]; n_fluid],
            proj_rho: Vec::new(),
            proj_lambda: Vec::new(),
            projection: (0, f64::NAN),
            dproj: Default::default(),
            last_h: 0.0,
            neighbors_fresh: false,
            n_static: n_fluid + walls.len(),
            bodies: Vec::new(),
            marker_local: Vec::new(),
            marker_owner: Vec::new(),
            body_origin: Vec::new(),
            marker_rows: Vec::new(),
            marker_rho: Vec::new(),
            marker_gamma: Vec::new(),
            marker_row_ids: Vec::new(),
            wall_rows: vec![RowBuf::default(); walls.len()],
            wall_rho: vec![settings.rest_density; walls.len()],
            wall_gamma: vec![0.0; walls.len()],
            wall_row_ids: Vec::new(),
            damping: 0.0,
            settings,
        })
    }

    /// Attach markers fixed in the frame of the body with handle `body` (`local`, m, in the
    /// body frame; e.g. [`box_markers`](crate::box_markers)): they enter the density sum
    /// and the density rows push the body (see the type's documentation). `current` is
    /// that body now (`system.body(handle)?`): the markers are placed at its pose, then at
    /// the body's pose at the start of every step. Attach a body once. Errors: a
    /// non-finite or empty marker set, a body attached twice; a handle that is not in the
    /// system is reported by the first step.
    pub fn attach_body(
        &mut self,
        body: BodyHandle,
        current: &RigidBody,
        local: &[[f64; 3]],
    ) -> Result<()> {
        if local.is_empty() {
            return Err(ChronoError::invalid(
                "attach_body.local",
                0,
                "a body needs at least one marker",
            ));
        }
        check_points("attach_body.local", local)?;
        if self.bodies.iter().any(|b| b.0 == body) {
            return Err(ChronoError::invalid(
                "attach_body.body",
                body,
                "this body is already attached",
            ));
        }
        let slot = self.bodies.len() as u32;
        self.bodies.push((body, self.marker_local.len()));
        for p in local {
            self.marker_local.push(Vector3::new(p[0], p[1], p[2]));
            self.marker_owner.push(slot);
            self.marker_rows.push(RowBuf::default());
            self.marker_rho.push(self.settings.rest_density);
            self.marker_gamma.push(0.0);
            for a in 0..3 {
                self.pos[a].push(0.0);
            }
        }
        self.body_origin.push([0.0; 3]);
        self.place_body(slot as usize, current);
        Ok(())
    }

    fn field(&self) -> DensityField<'_> {
        DensityField {
            kernel: &self.kernel,
            mass: self.kernel_mass,
            rho_0: self.settings.rest_density,
            grid: &self.grid,
            pos: [&self.pos[0], &self.pos[1], &self.pos[2]],
            nbrs: &self.nbrs,
            n_free: self.n_fluid,
            n_static: self.n_static,
            marker_owner: &self.marker_owner,
            body_origin: &self.body_origin,
        }
    }

    /// Place the markers of body slot `slot` at the pose of `body` (periodic axes wrapped).
    fn place_body(&mut self, slot: usize, body: &RigidBody) {
        let s = &self.settings;
        let first = self.bodies[slot].1;
        let end = self
            .bodies
            .get(slot + 1)
            .map_or(self.marker_local.len(), |b| b.1);
        let pose = body.pose();
        let x_b = body.position();
        self.body_origin[slot] = [x_b.x, x_b.y, x_b.z];
        for (k, r) in self.marker_local[first..end].iter().enumerate() {
            let x = pose * Point3::from(*r);
            let j = self.n_static + first + k;
            for a in 0..3 {
                let mut xa = x[a];
                if s.periodic[a] {
                    let lo = s.domain_lower[a];
                    xa = lo + (xa - lo).rem_euclid(s.domain_upper[a] - lo);
                }
                self.pos[a][j] = xa;
            }
        }
    }

    /// Place every body's markers at its pose in `bodies` (the system's bodies).
    fn place_markers(&mut self, bodies: &Bodies) -> Result<()> {
        for slot in 0..self.bodies.len() {
            let handle = self.bodies[slot].0;
            let body = bodies.get(handle).ok_or_else(|| {
                ChronoError::invalid(
                    "attach_body.body",
                    handle,
                    format!(
                        "constraint fluid \"{}\": no such body in the system",
                        self.name
                    ),
                )
            })?;
            self.place_body(slot, body);
        }
        Ok(())
    }

    /// Neighbours, densities and the density rows of the step (bodies at `q(l)`).
    fn build_rows(
        &mut self,
        ctx: &StepContext,
        bodies: &Bodies,
        rows: &mut ConstraintRows,
    ) -> Result<()> {
        let Some(first) = self.first_block else {
            return Ok(());
        };
        self.place_markers(bodies)?;
        self.refresh_neighbors()?;
        let mut rho = std::mem::take(&mut self.rho);
        let mut bufs = std::mem::take(&mut self.rows);
        let mut mbufs = std::mem::take(&mut self.marker_rows);
        let mut mrho = std::mem::take(&mut self.marker_rho);
        let mut wbufs = std::mem::take(&mut self.wall_rows);
        let mut wrho = std::mem::take(&mut self.wall_rho);
        let mut phi = std::mem::take(&mut self.phi);
        {
            let field = self.field();
            field.densities(&mut rho);
            if let Some(model) = &self.support_model {
                field.support_fractions(model, &mut phi);
            }
            if self.settings.gradient_correction > 0.0 {
                field.rows_corrected(&mut bufs, self.settings.gradient_correction);
            } else {
                field.rows(&mut bufs);
            }
            if self.settings.body_marker_rows {
                field.marker_rows(&mut mbufs, &mut mrho);
            }
            if self.settings.wall_marker_rows {
                field.wall_rows(&mut wbufs, &mut wrho);
            }
        }
        self.rho = rho;
        self.phi = phi;
        self.rows = bufs;
        self.marker_rows = mbufs;
        self.marker_rho = mrho;
        self.wall_rows = wbufs;
        self.wall_rho = wrho;
        if let Some(i) = self.rho.iter().position(|r| !r.is_finite()) {
            return Err(self.non_finite(ctx, i, "density"));
        }

        let h = ctx.h;
        let s = &self.settings;
        // with the inertial mass, a fluid without bodies solves the same problem as with
        // `m = m_k`, scaled (impulses by `m / m_k`): the mass does not change its motion
        let eps = compliance(s.compressibility, s.rest_density, h, self.mass);
        let mut entries = recycle(std::mem::take(&mut self.entries));
        self.row_ids.clear();
        let push = PushRow {
            first,
            bodies,
            slots: &self.bodies,
            settings: s,
            h,
            eps,
        };
        for ((buf, rho), phi) in self.rows.iter_mut().zip(&self.rho).zip(&self.phi) {
            let id = push.push(buf, *rho, *phi, false, &mut entries, rows);
            self.row_ids.push(id);
        }
        self.marker_row_ids.clear();
        if s.body_marker_rows {
            let (bufs, rho) = (&mut self.marker_rows, &self.marker_rho);
            push.push_markers(bufs, rho, &mut entries, rows, &mut self.marker_row_ids);
        }
        self.wall_row_ids.clear();
        if s.wall_marker_rows {
            let (bufs, rho) = (&mut self.wall_rows, &self.wall_rho);
            push.push_markers(bufs, rho, &mut entries, rows, &mut self.wall_row_ids);
        }
        self.entries = recycle(entries);
        Ok(())
    }

    fn refresh_neighbors(&mut self) -> Result<()> {
        let pos = [&self.pos[0][..], &self.pos[1][..], &self.pos[2][..]];
        self.grid.build(pos)?;
        self.grid
            .neighbor_list(pos, self.kernel.support(), &mut self.nbrs)?;
        self.neighbors_fresh = true;
        Ok(())
    }

    fn non_finite(&self, ctx: &StepContext, i: usize, what: &str) -> ChronoError {
        ChronoError::NonFinite {
            item: format!("constraint fluid \"{}\" (particle {i})", self.name),
            step: ctx.step,
            time: ctx.time,
            what: what.into(),
        }
    }
}

impl PhysicsItem for ConstraintFluid {
    fn name(&self) -> &str {
        &self.name
    }

    fn add_variables(&mut self, vars: &mut Variables) {
        let first = vars.add(self.mass_op.clone());
        for _ in 1..self.n_fluid {
            vars.add(self.mass_op.clone());
        }
        self.first_block = Some(first);
    }

    fn load_momentum(&self, ctx: &StepContext, vars: &Variables, k: &mut [f64]) {
        let Some(first) = self.first_block else {
            return;
        };
        let off = vars.offset(first);
        let g = ctx.gravity;
        for (i, v) in self.vel.iter().enumerate() {
            for a in 0..3 {
                k[off + 3 * i + a] += self.mass * (v[a] + ctx.h * g[a]);
            }
        }
    }

    fn collision_proxies(&self, out: &mut Vec<CollisionProxy>) {
        let s = &self.settings;
        if !s.body_contacts {
            return;
        }
        let material = ContactMaterial::with_friction(s.contact_friction);
        let radius = s.contact_radius_over_dp * s.spacing;
        out.reserve(self.n_fluid);
        for i in 0..self.n_fluid {
            let p = self.position(i);
            out.push(CollisionProxy {
                shape: ProxyShape::Sphere {
                    center: Vector3::new(p[0], p[1], p[2]),
                    radius,
                },
                material,
                id: i as u32,
            });
        }
    }

    /// Particle `proxy`'s own block along the three directions (no known velocity).
    fn proxy_jacobian(
        &self,
        proxy: u32,
        _p: &Vector3<f64>,
        dirs: &[Vector3<f64>; 3],
        entry: &mut dyn FnMut(BlockId, [&[f64]; 3]),
    ) -> [f64; 3] {
        if let Some(first) = self.first_block
            && (proxy as usize) < self.n_fluid
        {
            let [a, b, c] = dirs;
            entry(
                BlockId(first.0 + proxy),
                [a.as_slice(), b.as_slice(), c.as_slice()],
            );
        }
        [0.0; 3]
    }

    fn add_constraints(
        &mut self,
        ctx: &StepContext,
        _vars: &Variables,
        rows: &mut ConstraintRows,
    ) -> Result<()> {
        if self.bodies.is_empty() {
            self.build_rows(ctx, &Bodies::new(), rows)?;
        }
        Ok(())
    }

    fn add_body_constraints(
        &mut self,
        ctx: &StepContext,
        bodies: &Bodies,
        _vars: &Variables,
        rows: &mut ConstraintRows,
    ) -> Result<()> {
        if !self.bodies.is_empty() {
            self.build_rows(ctx, bodies, rows)?;
        }
        Ok(())
    }

    fn warm_start(&self, problem: &CcpProblem, gamma: &mut [f64]) {
        if self.row_ids.len() != self.n_fluid {
            return;
        }
        let f = self.settings.warm_start_factor;
        for (id, g) in self.row_ids.iter().zip(&self.gamma) {
            // a row that became unilateral is projected by the solver
            gamma[problem.row_index(*id)] = f * g;
        }
        for (k, id) in &self.marker_row_ids {
            gamma[problem.row_index(*id)] = f * self.marker_gamma[*k as usize];
        }
        for (k, id) in &self.wall_row_ids {
            gamma[problem.row_index(*id)] = f * self.wall_gamma[*k as usize];
        }
    }

    fn update(
        &mut self,
        ctx: &StepContext,
        vars: &Variables,
        v: &[f64],
        problem: &CcpProblem,
        gamma: &[f64],
    ) -> Result<()> {
        let Some(first) = self.first_block else {
            return Ok(());
        };
        let off = vars.offset(first);
        for (i, vi) in self.vel.iter_mut().enumerate() {
            *vi = [v[off + 3 * i], v[off + 3 * i + 1], v[off + 3 * i + 2]];
        }
        for (g, id) in self.gamma.iter_mut().zip(&self.row_ids) {
            *g = gamma[problem.row_index(*id)];
        }
        self.marker_gamma.fill(0.0);
        for (k, id) in &self.marker_row_ids {
            self.marker_gamma[*k as usize] = gamma[problem.row_index(*id)];
        }
        self.wall_gamma.fill(0.0);
        for (k, id) in &self.wall_row_ids {
            self.wall_gamma[*k as usize] = gamma[problem.row_index(*id)];
        }
        if let Some(i) = self
            .vel
            .iter()
            .position(|v| v.iter().any(|x| !x.is_finite()))
        {
            return Err(self.non_finite(ctx, i, "velocity after the solve"));
        }
        let eps = self.settings.xsph_epsilon(ctx.h);
        if eps > 0.0 && self.neighbors_fresh {
            let mut out = std::mem::take(&mut self.vel_scratch);
            if self.settings.xsph_corrected {
                self.field()
                    .xsph_corrected(eps, &self.rho, &self.vel, &mut out);
            } else {
                self.field().xsph(eps, &self.rho, &self.vel, &mut out);
            }
            self.vel_scratch = std::mem::replace(&mut self.vel, out);
        }
        let h = ctx.h;
        if self.damping > 0.0 {
            let f = (-self.damping * h).exp();
            for v in &mut self.vel {
                *v = v.map(|x| f * x);
            }
        }
        let s = &self.settings;
        for a in 0..3 {
            let (lo, hi) = (s.domain_lower[a], s.domain_upper[a]);
            let period = hi - lo;
            for (x, v) in self.pos[a][..self.n_fluid].iter_mut().zip(&self.vel) {
                *x += h * v[a];
                if s.periodic[a] {
                    *x = lo + (*x - lo).rem_euclid(period);
                }
            }
        }
        if let Some(i) = (0..self.n_fluid).find(|&i| (0..3).any(|a| !self.pos[a][i].is_finite())) {
            return Err(self.non_finite(ctx, i, "position after the step"));
        }
        self.project_positions()?;
        self.project_densities(ctx)?;
        if let Some(i) = (0..self.n_fluid).find(|&i| (0..3).any(|a| !self.pos[a][i].is_finite())) {
            return Err(self.non_finite(ctx, i, "position after the projection"));
        }
        self.last_h = h;
        self.neighbors_fresh = false;
        Ok(())
    }
}
