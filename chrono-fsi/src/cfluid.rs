//! Rigid bodies of every marker-carrying shape in a constraint fluid (chrono-cfluid): the
//! same BCE markers as the SPH coupling ([`crate::markers`]), attached to a
//! [`ConstraintFluid`] so that they enter its density rows, and the floating scene of
//! `fsi-floating-body` with `fluid = cfluid` ([`floating_cfluid`]).
//!
//! **The coupling** (H. Mazhar, PhD thesis, UW-Madison 2016; the seed's "Constraint
//! Fluids"): a body's markers, fixed in its frame, enter the SPH density sums of the fluid
//! particles near it, so the fluid next to the body sees a full kernel support; every
//! density row `C_i = rho_i / rho_0 - 1` then has a 6-entry block on the body
//! (`sum_k grad_k C_i` and `sum_k (x_k - x_b) x grad_k C_i` over its markers `k`), and the
//! row's pressure impulse pushes the body in the same CCP as the fluid, the contacts and
//! the joints: buoyancy and drag come out of the multipliers, and the momentum the fluid
//! gives a body is exactly the momentum the body gives the fluid (one solve, no
//! sub-steps, no explicit coupling limit). The fluid particles are also contact spheres
//! of the body's colliders (frictionless by default,
//! `CfluidSettings::contact_radius_over_dp`), which keeps them out of the body whatever the
//! rows do. Markers per shape and layer: [`crate::markers`] (box, sphere, horizontal or
//! any cylinder, ellipsoid; not capsules, hulls, meshes: an error naming the body); the
//! layers cover the kernel support (`wall_layers(h / dp)`), a body thinner than the
//! support or resolved by fewer than [`MIN_CELLS_ACROSS`](crate::builder::MIN_CELLS_ACROSS)
//! spacings is an error naming it, as for SPH.
//!
//! **The floating scene** ([`floating_cfluid`]): the geometry of [`crate::scene::floating`]
//! (the same [`FloatingParams`]: box and horizontal cylinder spanning a slab periodic in
//! y, sphere in a 3-D tank periodic in y), walls of fixed markers at both ends and the
//! floor with fixed box colliders behind them, the fluid lattice carved around the body
//! (points on or inside the surface removed, [`CARVE_DEPTH`]). A slab body's collider is
//! longer than the slab (no faces across y near the fluid); its markers are those of the
//! slab's span with the y faces left out. The fluid lattice is carved where a particle's
//! contact sphere would overlap the body (not only inside it, as for SPH). The still-water level and the draft are read
//! from the fluid's volume, `n dp^3` (the rows hold `rho_0`, so each particle stands for
//! its lattice cell), as for SPH ([`volume_draft`]).

use chrono_cfluid::floating_box::add_tank_colliders;
use chrono_cfluid::{CfluidSettings, ConstraintFluid, tank_markers};
use chrono_core::descriptor::CcpSolver;
use chrono_core::item::ItemHandle;
use chrono_core::math::{Isometry3, Point3, UnitQuaternion, Vector3};
use chrono_core::particles::lattice::{Fit, Lattice, SLAB_SIDES, slab_layers, wall_layers};
use chrono_core::{BodyHandle, ContactMaterial, RigidBodyBuilder, Shape, System, SystemSettings};

use crate::builder::{CARVE_DEPTH, collider_markers, open_axes, signed_distance};
use crate::error::{FsiError, Result};
use crate::scene::{
    BOX_ASPECT, FloatShape, FloatingParams, FloatingSystem, PLANAR_INERTIA, archimedes_draft,
    submerged_area_or_volume, volume_draft,
};

/// Attach `body` of `system` to the constraint fluid `fluid` with markers generated from
/// its colliders at the fluid's spacing (the module docs); a collider that spans a
/// periodic direction of the fluid's domain gets no faces across it. Returns the number
/// of markers. Errors name the body (no collider, a shape without markers, too thin or
/// unresolved) or come from [`ConstraintFluid::attach_body`].
pub fn attach_body(
    fluid: &mut ConstraintFluid,
    system: &System,
    body: BodyHandle,
) -> Result<usize> {
    let b = system.body(body)?;
    let name = body_name(system, body)?;
    if b.colliders().is_empty() {
        return Err(FsiError::NoShape { body: name });
    }
    let s = fluid.settings().clone();
    let mut local = Vec::new();
    for c in b.colliders() {
        let open = open_axes(
            s.periodic,
            s.domain_lower,
            s.domain_upper,
            b,
            &c.shape,
            &c.local_pose,
        );
        local.extend(shape_markers_of(
            fluid,
            &name,
            &c.shape,
            &c.local_pose,
            open,
        )?);
    }
    fluid.attach_body(body, b, &local)?;
    Ok(local.len())
}

/// Attach `body` of `system` to `fluid` with the markers of `shape` placed at `local` in
/// the body frame, the faces normal to the `open` local axes left out: for a body whose
/// collider differs from its wetted shape (a slab body whose collider reaches beyond the
/// periodic slab). Returns the number of markers; errors as [`attach_body`].
pub fn attach_shape(
    fluid: &mut ConstraintFluid,
    system: &System,
    body: BodyHandle,
    shape: &Shape,
    local: &Isometry3<f64>,
    open: [bool; 3],
) -> Result<usize> {
    let name = body_name(system, body)?;
    let pts = shape_markers_of(fluid, &name, shape, local, open)?;
    fluid.attach_body(body, system.body(body)?, &pts)?;
    Ok(pts.len())
}

fn body_name(system: &System, body: BodyHandle) -> Result<String> {
    let b = system.body(body)?;
    Ok(if b.name().is_empty() {
        format!("{body}")
    } else {
        b.name().to_string()
    })
}

fn shape_markers_of(
    fluid: &ConstraintFluid,
    name: &str,
    shape: &Shape,
    local: &Isometry3<f64>,
    open: [bool; 3],
) -> Result<Vec<[f64; 3]>> {
    let s = fluid.settings();
    collider_markers(
        name,
        shape,
        local,
        open,
        s.spacing,
        fluid.kernel().support(),
        wall_layers(s.h_over_dp),
    )
}

/// Settings of the constraint fluid in [`floating_cfluid`] beyond the scene's geometry.
#[derive(Debug, Clone, PartialEq)]
pub struct CfluidFloat {
    /// `h_k / dp` of the constraint fluid (chrono-cfluid's default 1.2).
    pub h_over_dp: f64,
    /// XSPH smoothing epsilon (chrono-cfluid's default 0.1).
    pub xsph: f64,
    /// Radius of the particles' contact spheres over the spacing (default 0.5).
    pub contact_radius: f64,
    /// `CfluidSettings::surface_deficit` (default 0: every density deficit is a free
    /// surface). The fluid next to a curved body starts with deficits of 10-25 % (the
    /// markers of a convex surface fill less of the kernel support than a wall's, and
    /// the first layer stands a contact radius off), and with unilateral rows it gives
    /// the body no suction (docs/validation-fsi.md, "Constraint fluids").
    pub surface_deficit: f64,
}

impl Default for CfluidFloat {
    fn default() -> Self {
        let d = CfluidSettings::default();
        Self {
            h_over_dp: d.h_over_dp,
            xsph: d.xsph,
            contact_radius: d.contact_radius_over_dp,
            surface_deficit: d.surface_deficit,
        }
    }
}

/// The floating scene with a constraint fluid: the system, the body, the fluid item and
/// the geometry.
pub struct CfluidFloatingScene {
    /// The multibody system (gravity `-g z`): tank colliders, the body, the fluid item.
    pub system: System,
    /// The floating body.
    pub body: BodyHandle,
    /// The fluid item ([`ConstraintFluid`]).
    pub fluid: ItemHandle,
    /// Tank inner extent (x, y), m.
    pub tank: [f64; 2],
    /// Archimedes draft, m.
    pub draft_archimedes: f64,
    /// The fluid's vertical force on the body over the last [`FloatingSystem::step`], N.
    force_z: f64,
}

impl FloatingSystem for CfluidFloatingScene {
    fn system(&self) -> &System {
        &self.system
    }
    fn system_mut(&mut self) -> &mut System {
        &mut self.system
    }
    fn body(&self) -> BodyHandle {
        self.body
    }
    fn tank(&self) -> [f64; 2] {
        self.tank
    }
    fn set_fluid_damping(&mut self, rate: f64) -> Result<()> {
        self.fluid_mut().set_damping(rate)?;
        Ok(())
    }
    /// The step, and the fluid's force on the body from the body's momentum change:
    /// `F = m (v' - v) / h - m g` (density rows and the particles' contacts together;
    /// the body has no other load).
    fn step(&mut self, h: f64) -> Result<()> {
        let v0 = self.system.body(self.body)?.linear_velocity().z;
        self.system.step(h)?;
        let b = self.system.body(self.body)?;
        let g = self.system.settings().gravity.z;
        self.force_z = b.mass() * ((b.linear_velocity().z - v0) / h - g);
        Ok(())
    }
    fn fluid_force_z(&self) -> f64 {
        self.force_z
    }
    fn fluid_steps(&self) -> u64 {
        self.system.step_count()
    }
}

impl CfluidFloatingScene {
    /// The fluid.
    pub fn fluid(&self) -> &ConstraintFluid {
        self.system
            .item::<ConstraintFluid>(self.fluid)
            .expect("the scene's fluid")
    }

    /// The fluid, mutable (its damping, XSPH).
    pub fn fluid_mut(&mut self) -> &mut ConstraintFluid {
        self.system
            .item_mut::<ConstraintFluid>(self.fluid)
            .expect("the scene's fluid")
    }

    /// The body's draft (m): the still-water level of the fluid's volume `n m / rho_0`
    /// (each particle its lattice cell; the rows hold `rho_0`) around the body, minus the
    /// body's lowest point ([`volume_draft`]).
    pub fn draft(&self, p: &FloatingParams) -> f64 {
        let f = self.fluid();
        let vol = f.n_fluid() as f64 * f.particle_mass() / f.settings().rest_density;
        let c = self
            .system
            .body(self.body)
            .expect("the scene's body")
            .position();
        volume_draft(p.shape, p.body_size, self.tank, vol, c.z)
    }
}

/// Builds the floating scene of `p` (its geometry and densities; the SPH-only fields
/// `h_over_dp`, `mach_factor`, `artificial_viscosity`, `xsph` and `nu` are not used) in a
/// constraint fluid set by `c`, solved by `solver` (for example `chrono_ccp::Apgd`). See
/// the [module docs](self).
pub fn floating_cfluid(
    p: &FloatingParams,
    c: &CfluidFloat,
    solver: Box<dyn CcpSolver>,
) -> Result<CfluidFloatingScene> {
    p.validate()?;
    let dp = p.spacing;
    let s = p.body_size;
    let layers = wall_layers(c.h_over_dp);
    let t = layers as f64 * dp;
    let len = (p.length * s / dp).round() * dp;
    let (width, slab) = match p.shape {
        FloatShape::Sphere => ((p.width * s / dp).round() * dp, false),
        _ => (slab_layers(c.h_over_dp) as f64 * dp, true),
    };
    let level = (p.depth / dp + 1e-6).floor() * dp;
    let top = level + s + 4.0 * dp;
    let draft = archimedes_draft(p.shape, s, p.body_density / p.rho0);
    let settings = CfluidSettings {
        spacing: dp,
        rest_density: p.rho0,
        h_over_dp: c.h_over_dp,
        xsph: c.xsph,
        contact_radius_over_dp: c.contact_radius,
        surface_deficit: c.surface_deficit,
        domain_lower: [-t, 0.0, -t],
        domain_upper: [len + t, width, top + t],
        periodic: [false, true, false],
        ..CfluidSettings::default()
    };
    settings.validate()?;
    let mut system = System::new(
        SystemSettings {
            envelope: 0.25 * dp,
            ..SystemSettings::default()
        },
        solver,
    )?;
    // the wetted shape (markers, carving) spans the slab; the collider reaches beyond it
    let big = 4.0 * width;
    let (wet, collider) = match p.shape {
        FloatShape::Box => (
            Shape::Box {
                half_extents: Vector3::new(0.5 * BOX_ASPECT * s, 0.5 * width, 0.5 * s),
            },
            Shape::Box {
                half_extents: Vector3::new(0.5 * BOX_ASPECT * s, big, 0.5 * s),
            },
        ),
        FloatShape::Cylinder => (
            Shape::Cylinder {
                half_length: 0.5 * width,
                radius: 0.5 * s,
            },
            Shape::Cylinder {
                half_length: big,
                radius: 0.5 * s,
            },
        ),
        FloatShape::Sphere => {
            let ball = Shape::Sphere { radius: 0.5 * s };
            (ball.clone(), ball)
        }
    };
    let open = [false, slab, false];
    let centre = Vector3::new(0.5 * len, 0.5 * width, level - draft + 0.5 * s + p.offset);
    let material = ContactMaterial::with_friction(0.3);
    let mut builder = RigidBodyBuilder::dynamic()
        .name("float")
        .mass_from_shape(&wet, p.body_density)?;
    if slab {
        let m = p.body_density * submerged_area_or_volume(p.shape, s, s) * width;
        let iy = match p.shape {
            FloatShape::Box => m * (BOX_ASPECT * BOX_ASPECT + 1.0) * s * s / 12.0,
            _ => 0.125 * m * s * s,
        };
        builder =
            builder.inertia_diagonal(Vector3::new(PLANAR_INERTIA * iy, iy, PLANAR_INERTIA * iy));
    }
    let body = system.add_body(
        builder
            .position(centre)
            .rotation(UnitQuaternion::identity())
            .collider(collider, Isometry3::identity(), material),
    )?;
    // fixed tank colliders behind the marker walls (floor, both ends): the fluid's contact
    // spheres and a sinking body land on them
    add_tank_colliders(&mut system, [len, width, top], t, material)?;
    // the fluid lattice, carved around the body: a point closer to the surface than its
    // contact sphere's radius goes (on a curved surface the lattice comes anywhere from 0
    // to dp / 2 close; an overlapping contact sphere would be pushed out at the contact's
    // recovery speed and kick a light body off); on the surface at least, as the SPH
    // builder ([`CARVE_DEPTH`]); the tolerance keeps the carving symmetric under round-off.
    // The fluid's volume is read from its particle count, so the carving moves the
    // still-water level, not the draft's reference.
    let carve = (CARVE_DEPTH + 1e-6).max(c.contact_radius - 1e-6) * dp;
    let lattice = Lattice::new([0.0; 3], dp)?;
    let fluid: Vec<[f64; 3]> = lattice
        .fill([0.0; 3], [len, width, level], Fit::Floor)?
        .into_iter()
        .filter(|q| {
            let l = Point3::new(q[0] - centre.x, q[1] - centre.y, q[2] - centre.z);
            signed_distance(&wet, [l.x, l.y, l.z], open) > carve
        })
        .collect();
    let walls = tank_markers([0.0; 3], [len, width, top], dp, layers, SLAB_SIDES)?;
    let mut item = ConstraintFluid::new("water", settings, &fluid, &walls)?;
    attach_shape(&mut item, &system, body, &wet, &Isometry3::identity(), open)?;
    let fluid = system.add_item(Box::new(item));
    Ok(CfluidFloatingScene {
        system,
        body,
        fluid,
        tank: [len, width],
        draft_archimedes: draft,
        force_z: f64::NAN,
    })
}
