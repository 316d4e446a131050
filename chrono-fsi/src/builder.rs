//! [`FsiBuilder`]: an SPH fluid with tanks and fluid blocks, carved around rigid bodies
//! that carry BCE markers.

use chrono_core::math::{Isometry3, Point3, Vector3};
use chrono_core::particles::lattice::{Fit, Lattice, wall_layers};
use chrono_core::{BodyHandle, RigidBody, Shape, System};
use chrono_sph::{RigidMotion, SphBuilder, SphSettings};

use chrono_core::item::PhysicsItem;
use chrono_fea::CableItem;

use crate::cable::{CableMarkers, cable_distance, node_uses};
use crate::error::{FsiError, Result};
use crate::fluid::{Coupled, CoupledCable, SphFluid};
use crate::markers::{shape_kind, shape_markers, thickness};

/// The signed distance from a body's surface (in spacings) up to which fluid lattice
/// points are removed: `0`, the points inside the body and on its surface (a point on a
/// face that lies on a lattice plane stands for a cell half inside; it goes, so such a
/// face keeps the rule of a tank wall, the first layer `dp` off). A threshold of `dp / 2` (the
/// earlier rule: the first layer no closer than `dp / 2`) is exact for a face on the
/// lattice, but off the lattice, and on every curved surface, it leaves a fluid-free gap
/// of `dp / 4` to `dp / 2` on average: measured, the gap made a horizontal cylinder and a
/// sphere float 11 % and 9 % too high (`fsi-floating-body --quick`) and a square array of
/// cylinders drag 9-18 % less than Sangani & Acrivos (`fsi-cylinder-array`; the gap acts
/// as a slip layer). See docs/validation-fsi.md.
pub const CARVE_DEPTH: f64 = 0.0;

/// Fewest fluid spacings across a body's smallest dimension: below it the markers cannot
/// represent the shape (a sphere of 3 spacings is a lumpy cluster).
pub const MIN_CELLS_ACROSS: f64 = 4.0;

/// A body's collider in the body frame and the local axes that are open (periodic span).
#[derive(Debug, Clone)]
struct BodyShape {
    shape: Shape,
    local_pose: Isometry3<f64>,
    open: [bool; 3],
}

#[derive(Debug, Clone)]
struct PendingBody {
    handle: BodyHandle,
    name: String,
    pose: Isometry3<f64>,
    shapes: Vec<BodyShape>,
    local_markers: Vec<[f64; 3]>,
    /// A fixed body: not a source of the active domain.
    fixed: bool,
}

/// Builds an [`SphFluid`]: SPH settings, tanks ([`sph`](Self::sph)), fluid blocks
/// carved around the coupled bodies, and the bodies' BCE markers
/// ([`markers`](crate::markers)).
///
/// Fluid lattice points whose centre lies inside a body or a cable's section are removed
/// ([`CARVE_DEPTH`]): each point stands for its lattice cell of fluid, so the fluid keeps
/// the volume outside the body up to the lattice's round-off, and the first fluid layer
/// stands on average `dp / 2` off the surface (the outer marker layer `dp / 2` below it),
/// as at a tank wall, whatever the body's shape and position on the lattice. Every body
/// gets `wall_layers(h / dp)` marker layers (they cover the kernel support `2 h`).
#[derive(Debug)]
pub struct FsiBuilder {
    sph: SphBuilder,
    fluid: Vec<(Vec<[f64; 3]>, Option<f64>)>,
    bodies: Vec<PendingBody>,
    cables: Vec<CoupledCable>,
}

impl FsiBuilder {
    /// A builder with the fluid's settings (validated).
    pub fn new(settings: SphSettings) -> Result<Self> {
        Ok(Self {
            sph: SphBuilder::new(settings)?,
            fluid: Vec::new(),
            bodies: Vec::new(),
            cables: Vec::new(),
        })
    }

    /// The SPH builder, for tanks and fixed wall boxes
    /// ([`SphBuilder::add_tank`]); add fluid through [`add_fluid_box`](Self::add_fluid_box)
    /// so it is carved around the bodies.
    pub fn sph(&mut self) -> &mut SphBuilder {
        &mut self.sph
    }

    /// The fluid settings.
    pub fn settings(&self) -> &SphSettings {
        self.sph.settings()
    }

    /// A block of fluid on the lattice (see [`SphBuilder::add_fluid_box`]), hydrostatic
    /// below `free_surface` (m) when given; carved around the bodies at
    /// [`build`](Self::build).
    pub fn add_fluid_box(
        &mut self,
        lower: [f64; 3],
        upper: [f64; 3],
        free_surface: Option<f64>,
    ) -> Result<()> {
        for a in 0..3 {
            if !(lower[a].is_finite() && upper[a].is_finite() && upper[a] > lower[a]) {
                return Err(FsiError::invalid(
                    format!("fluid_box.upper[{a}]"),
                    upper[a],
                    format!("must be finite and exceed lower[{a}] = {}", lower[a]),
                ));
            }
        }
        let dp = self.settings().spacing;
        let points = Lattice::new(lower, dp)?.fill(lower, upper, Fit::Floor)?;
        self.fluid.push((points, free_surface));
        Ok(())
    }

    /// Couple `body` of `system` to the fluid: markers from each of its colliders (box,
    /// sphere, cylinder) at the fluid spacing, placed at its current pose. Errors name the
    /// body: a shape without markers, a body thinner than the kernel support or resolved
    /// by fewer than [`MIN_CELLS_ACROSS`] spacings, a body without collider.
    pub fn add_body(&mut self, system: &System, body: BodyHandle) -> Result<usize> {
        let b = system.body(body)?;
        let name = if b.name().is_empty() {
            format!("{body}")
        } else {
            b.name().to_string()
        };
        if b.colliders().is_empty() {
            return Err(FsiError::NoShape { body: name });
        }
        let s = self.settings();
        let (dp, support) = (s.spacing, 2.0 * s.h());
        let layers = wall_layers(s.h_over_dp);
        let mut shapes = Vec::new();
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
            local.extend(collider_markers(
                &name,
                &c.shape,
                &c.local_pose,
                open,
                dp,
                support,
                layers,
            )?);
            shapes.push(BodyShape {
                shape: c.shape.clone(),
                local_pose: c.local_pose,
                open,
            });
        }
        let n = local.len();
        self.bodies.push(PendingBody {
            handle: body,
            name,
            pose: b.pose(),
            shapes,
            local_markers: local,
            fixed: b.motion() == chrono_core::BodyMotion::Fixed,
        });
        Ok(n)
    }

    /// Couple the ANCF cable `item` to the fluid: BCE markers over the round section of
    /// each element's area at the fluid spacing ([`crate::cable`]), placed at its current
    /// configuration. The fluid item owns the cable from then on
    /// ([`SphFluid::cable`]). Returns the cable's index. Errors name the cable and the
    /// element: a section thinner than the kernel support or resolved by fewer than
    /// [`MIN_CELLS_ACROSS`] spacings.
    pub fn add_cable(&mut self, item: CableItem) -> Result<usize> {
        let s = self.settings();
        let (dp, support) = (s.spacing, 2.0 * s.h());
        let markers = CableMarkers::new(item.name(), item.mesh(), dp, support)?;
        let mut c = CoupledCable::new(item, markers, usize::MAX);
        c.place()?;
        self.cables.push(c);
        Ok(self.cables.len() - 1)
    }

    /// The fluid item named `name`: fluid blocks carved around the bodies and cables, the
    /// bodies' markers as rigid carriers (one wall group per body, `group_base + k`), the
    /// cables' as point carriers (groups after the bodies').
    pub fn build(mut self, name: impl Into<String>, group_base: u16) -> Result<SphFluid> {
        let dp = self.settings().spacing;
        let fluid = std::mem::take(&mut self.fluid);
        let uses: Vec<Vec<u32>> = self
            .cables
            .iter()
            .map(|c| node_uses(c.item.mesh()))
            .collect();
        for (points, free_surface) in fluid {
            let kept: Vec<[f64; 3]> = points
                .into_iter()
                .filter(|p| {
                    let x = Vector3::new(p[0], p[1], p[2]);
                    self.bodies.iter().all(|b| {
                        b.shapes.iter().all(|s| {
                            let pl = (b.pose * s.local_pose).inverse_transform_point(&x.into());
                            // a point on the surface goes (its cell is half inside; see
                            // CARVE_DEPTH); the tolerance keeps the carving mirror-symmetric
                            // under round-off
                            signed_distance(&s.shape, [pl.x, pl.y, pl.z], s.open)
                                > (CARVE_DEPTH + 1e-6) * dp
                        })
                    }) && self.cables.iter().zip(&uses).all(|(c, u)| {
                        cable_distance(c.item.mesh(), u, &x) > (CARVE_DEPTH + 1e-6) * dp
                    })
                })
                .collect();
            self.sph.add_fluid_points(&kept, free_surface);
        }
        let mut coupled = Vec::new();
        for (k, b) in self.bodies.iter().enumerate() {
            let motion = RigidMotion::at_rest(b.pose.translation.vector, b.pose.rotation);
            let carrier =
                self.sph
                    .add_rigid_markers(motion, &b.local_markers, group_base + k as u16)?;
            coupled.push(Coupled {
                handle: b.handle,
                name: b.name.clone(),
                carrier,
                markers: b.local_markers.len(),
                load: [Vector3::zeros(); 2],
            });
        }
        let mut cables = std::mem::take(&mut self.cables);
        let base = group_base + self.bodies.len() as u16;
        for (k, c) in cables.iter_mut().enumerate() {
            c.carrier = self.sph.add_point_markers(&c.x, base + k as u16)?;
        }
        let mut sph = self.sph.build()?;
        // the active domain follows the bodies that move (dynamic or kinematic) and the
        // cables
        for (b, c) in self.bodies.iter().zip(&coupled) {
            sph.set_carrier_source(c.carrier, !b.fixed)?;
        }
        for c in &cables {
            // the markers move with the cable's initial velocity from t = 0
            sph.set_point_motion(c.carrier, 0.0, &c.x, &c.v)?;
        }
        Ok(SphFluid::new(name.into(), sph, coupled, cables))
    }
}

/// The markers of one collider of body `name` (m, in the body frame): `shape`'s
/// [`shape_markers`] at spacing `dp`, `layers` deep, placed by the collider's `local`
/// pose, `open` axes left out. Errors name the body: a shape without markers, a shape
/// thinner than the kernel `support` (m) or resolved by fewer than
/// [`MIN_CELLS_ACROSS`] spacings. Shared by the SPH ([`FsiBuilder::add_body`]) and the
/// constraint-fluid ([`crate::cfluid`]) couplings.
pub fn collider_markers(
    name: &str,
    shape: &Shape,
    local: &Isometry3<f64>,
    open: [bool; 3],
    dp: f64,
    support: f64,
    layers: usize,
) -> Result<Vec<[f64; 3]>> {
    let kind = shape_kind(shape);
    let t = thickness(shape, open).ok_or_else(|| FsiError::UnsupportedShape {
        body: name.to_string(),
        shape: kind.to_string(),
    })?;
    if t < support {
        return Err(FsiError::BodyThinnerThanSupport {
            body: name.to_string(),
            shape: kind.to_string(),
            thickness: t,
            support,
        });
    }
    if t < MIN_CELLS_ACROSS * dp {
        return Err(FsiError::Unresolved {
            body: name.to_string(),
            shape: kind.to_string(),
            thickness: t,
            spacing: dp,
            min_cells: MIN_CELLS_ACROSS,
        });
    }
    let m = shape_markers(name, shape, dp, layers, open)?;
    Ok(m.points
        .iter()
        .map(|p| {
            let q = local * Point3::new(p[0], p[1], p[2]);
            [q.x, q.y, q.z]
        })
        .collect())
}

/// The local axes of a collider that span a periodic direction of the fluid domain: the
/// axis is parallel to a periodic world axis and the shape is at least one period long.
/// The local axes of a collider (`shape` at `local` in body `b`) along which it spans a
/// periodic direction of the fluid domain `[lower, upper]` (`periodic` per axis): the
/// faces or caps normal to them get no markers and cut no fluid.
pub fn open_axes(
    periodic: [bool; 3],
    lower: [f64; 3],
    upper: [f64; 3],
    b: &RigidBody,
    shape: &Shape,
    local: &Isometry3<f64>,
) -> [bool; 3] {
    let extent = |i: usize| match shape {
        Shape::Box { half_extents } => 2.0 * half_extents[i],
        Shape::Cylinder { half_length, .. } if i == 1 => 2.0 * half_length,
        _ => 0.0,
    };
    let rot = b.rotation() * local.rotation;
    let mut open = [false; 3];
    for (i, o) in open.iter_mut().enumerate() {
        let dir = rot * Vector3::ith(i, 1.0);
        for a in 0..3 {
            let period = upper[a] - lower[a];
            if periodic[a] && dir[a].abs() > 1.0 - 1e-9 && extent(i) >= period * (1.0 - 1e-9) {
                *o = true;
            }
        }
    }
    open
}

/// Signed distance of the shape-local point `p` to the surface of `shape` (m, negative
/// inside), the `open` axes ignored; `+inf` for shapes without markers.
pub fn signed_distance(shape: &Shape, p: [f64; 3], open: [bool; 3]) -> f64 {
    match shape {
        Shape::Sphere { radius } => (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt() - radius,
        Shape::Ellipsoid { semi_axes } => chrono_core::shape::ellipsoid_signed_distance(
            semi_axes,
            &chrono_core::math::Vector3::new(p[0], p[1], p[2]),
        ),
        Shape::Box { half_extents } => {
            let q: Vec<f64> = (0..3)
                .map(|i| {
                    if open[i] {
                        f64::NEG_INFINITY
                    } else {
                        p[i].abs() - half_extents[i]
                    }
                })
                .collect();
            box_distance(&q)
        }
        Shape::Cylinder {
            half_length,
            radius,
        } => {
            let dr = (p[0] * p[0] + p[2] * p[2]).sqrt() - radius;
            let dy = if open[1] {
                f64::NEG_INFINITY
            } else {
                p[1].abs() - half_length
            };
            box_distance(&[dr, dy])
        }
        _ => f64::INFINITY,
    }
}

/// The distance function of an intersection of slabs from the per-axis excesses `q`
/// (`-inf` for an ignored axis): outside, the norm of the positive parts; inside, the
/// largest (least negative) excess.
fn box_distance(q: &[f64]) -> f64 {
    let out: f64 = q.iter().map(|&x| x.max(0.0).powi(2)).sum::<f64>().sqrt();
    let inside = q.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    if out > 0.0 { out } else { inside }
}
