//! A flat-bottomed cylindrical silo with a circular orifice in its floor, and the recycling
//! of the discharged grains that keeps its head constant.
//!
//! The wall is a regular polygon of half-spaces ([`super::add_cylinder_wall`]); the floor
//! is a triangle-mesh annulus ([`annulus`]) whose hole has the orifice's area. A grain that
//! has fallen below the floor is counted as discharged, removed, and replaced by a new one
//! at rest on top of the pile ([`Recycler::recycle`]), so the flow is steady after the
//! initial collapse. The mass
//! flow rate of such a silo follows Beverloo's law (W. A. Beverloo, H. A. Leniger and
//! J. van de Velde, Chem. Eng. Sci. 15, 1961): `W = C rho_b sqrt(g) (D - k d)^(5/2)`.

use nalgebra::{Isometry3, Vector3};

use super::add_cylinder_wall;
use super::bed::Bed;
use super::fill::Region;
use crate::body::{BodyHandle, BodyMotion, RigidBody, RigidBodyBuilder};
use crate::error::{ChronoError, Result, check_positive};
use crate::material::ContactMaterial;
use crate::rng::Rng;
use crate::shape::Shape;
use crate::system::System;

/// The floor of a silo: a triangle-mesh annulus in the plane `z = 0` between the hole
/// radius `r_in` (m; the polygon's area equals the circle's) and `r_out` (m; the polygon
/// circumscribes the circle), `sides` sides, normals up.
pub fn annulus(r_in: f64, r_out: f64, sides: usize) -> Shape {
    let n = sides as f64;
    let a = std::f64::consts::TAU / n;
    // Equal area: n/2 R^2 sin(a) = pi r^2.
    let scale = (std::f64::consts::PI / (0.5 * n * a.sin())).sqrt();
    let (ri, ro) = (r_in * scale, r_out / (0.5 * a).cos());
    let mut vertices = Vec::with_capacity(2 * sides);
    for k in 0..sides {
        let (s, c) = (a * k as f64).sin_cos();
        vertices.push(Vector3::new(ri * c, ri * s, 0.0));
        vertices.push(Vector3::new(ro * c, ro * s, 0.0));
    }
    let mut indices = Vec::with_capacity(2 * sides);
    for k in 0..sides as u32 {
        let (i0, o0) = (2 * k, 2 * k + 1);
        let (i1, o1) = (
            (2 * k + 2) % (2 * sides as u32),
            (2 * k + 3) % (2 * sides as u32),
        );
        // Counter-clockwise seen from above (+z).
        indices.push([i0, o0, o1]);
        indices.push([i0, o1, i1]);
    }
    Shape::TriMesh { vertices, indices }
}

/// A flat-bottomed cylindrical silo standing on `z = 0`, axis along Z through the origin.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Silo {
    /// Inner diameter of the wall, m.
    pub diameter: f64,
    /// Diameter of the circular orifice in the floor, m.
    pub orifice: f64,
    /// How far the floor reaches beyond the wall, m (so no grain slips between them).
    pub floor_margin: f64,
    /// Sides of the wall's polygon (its inscribed circle is the wall).
    pub wall_sides: usize,
    /// Sides of the floor's annulus.
    pub floor_sides: usize,
    /// Contact material of the wall and the floor.
    pub material: ContactMaterial,
}

/// The bodies of a silo.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SiloBodies {
    /// The wall (fixed, named "silo wall").
    pub wall: BodyHandle,
    /// The floor (fixed, named "floor").
    pub floor: BodyHandle,
}

impl Silo {
    /// A silo of `diameter` with an `orifice` (m): a 32-sided wall, a 48-sided floor
    /// reaching `floor_margin` beyond it.
    pub fn new(diameter: f64, orifice: f64, floor_margin: f64, material: ContactMaterial) -> Self {
        Self {
            diameter,
            orifice,
            floor_margin,
            wall_sides: 32,
            floor_sides: 48,
            material,
        }
    }

    /// Adds the wall, then the floor, to `sys`. Errors name the bad field.
    pub fn add(&self, sys: &mut System) -> Result<SiloBodies> {
        check_positive("silo.diameter", self.diameter)?;
        check_positive("silo.orifice", self.orifice)?;
        if self.orifice >= self.diameter {
            return Err(ChronoError::invalid(
                "silo.orifice",
                self.orifice,
                format!("must be below silo.diameter = {}", self.diameter),
            ));
        }
        if self.floor_sides < 3 {
            return Err(ChronoError::invalid(
                "silo.floor_sides",
                self.floor_sides,
                "must be >= 3",
            ));
        }
        let wall = add_cylinder_wall(
            sys,
            "silo wall",
            Vector3::zeros(),
            0.5 * self.diameter,
            self.wall_sides,
            self.material,
        )?;
        let floor = sys.add_body(RigidBodyBuilder::fixed().name("floor").collider(
            annulus(
                0.5 * self.orifice,
                0.5 * self.diameter + self.floor_margin,
                self.floor_sides,
            ),
            Isometry3::identity(),
            self.material,
        ))?;
        Ok(SiloBodies { wall, floor })
    }

    /// The silo's inside from `bottom` (m) up by `height` (m): the region for a
    /// [`GrainBed`](super::GrainBed) poured into it.
    pub fn region(&self, bottom: f64, height: f64) -> Region {
        Region::Cylinder {
            base: Vector3::new(0.0, 0.0, bottom),
            radius: 0.5 * self.diameter,
            height,
        }
    }
}

/// Replaces the grains that left a silo by new ones on top of the pile, and counts the mass
/// that left.
///
/// A discharged grain is removed from the system ([`System::remove_bodies`], all of a step
/// at once) and a new grain like it (same name, mass, inertia, colliders) is added at rest
/// at a free spot above the pile: its handle takes the old one's place in
/// [`handles`](Recycler::handles), the old handle is stale. The bed's own handle list
/// ([`Bed::handles`]) goes stale as grains are recycled: read the grains through
/// [`handles`](Recycler::handles).
#[derive(Debug, Clone)]
pub struct Recycler {
    handles: Vec<BodyHandle>,
    masses: Vec<f64>,
    rng: Rng,
    /// A grain whose centre is below this height (m) has left the silo.
    below: f64,
    /// Lowest height of re-insertion (m).
    insert_height: f64,
    /// Re-inserted centres lie within this distance of the axis (m).
    insert_radius: f64,
    /// Grain diameter `d` (m): re-inserted grains keep `1.05 d` from the grains near the
    /// insertion height, and rise by `d` every 8 tries.
    diameter: f64,
    discharged: f64,
    near_top: Vec<Vector3<f64>>,
}

impl Recycler {
    /// Recycling for the grains of `bed` in `silo` (largest grain diameter `d`, m): a grain
    /// below `5 d` under the floor is re-inserted at rest at a random place at or above
    /// `insert_height` (m), at least `1.05 d` from the grains there. The random places
    /// continue the bed's generator ([`Bed::rng`]).
    pub fn new(sys: &System, bed: &Bed, silo: &Silo, d: f64, insert_height: f64) -> Result<Self> {
        check_positive("recycler.d", d)?;
        Ok(Self {
            handles: bed.handles.clone(),
            masses: bed.masses(sys)?,
            rng: bed.rng.clone(),
            below: -5.0 * d,
            insert_height,
            insert_radius: 0.5 * silo.diameter - 0.5 * d,
            diameter: d,
            discharged: 0.0,
            near_top: Vec::new(),
        })
    }

    /// Mass discharged so far, kg.
    pub fn discharged(&self) -> f64 {
        self.discharged
    }

    /// The grains' masses (kg), in the bed's order.
    pub fn masses(&self) -> &[f64] {
        &self.masses
    }

    /// The grains' current handles, in the bed's order (a recycled grain's new handle in
    /// its predecessor's place).
    pub fn handles(&self) -> &[BodyHandle] {
        &self.handles
    }

    /// Counts and recycles the grains that have left the silo since the last call (call it
    /// after every step): removes them (one batch) and adds their replacements at rest;
    /// returns how many.
    pub fn recycle(&mut self, sys: &mut System) -> Result<usize> {
        let d = self.diameter;
        // A fixed insertion height, not one measured from the grains (it would follow the
        // rain of recycled grains upwards); a free spot, since an overlap would launch the
        // grain under SMC's penalty forces.
        self.near_top.clear();
        for &b in &self.handles {
            let x = sys.body(b)?.position();
            if x.z > self.insert_height - 1.5 * d {
                self.near_top.push(x);
            }
        }
        let mut gone: Vec<(usize, Vector3<f64>)> = Vec::new();
        for (k, &b) in self.handles.iter().enumerate() {
            if sys.body(b)?.position().z > self.below {
                continue;
            }
            self.discharged += self.masses[k];
            let mut at = Vector3::zeros();
            for attempt in 0.. {
                let rad = self.insert_radius * self.rng.uniform().sqrt();
                let phi = std::f64::consts::TAU * self.rng.uniform();
                let z = self.insert_height + d * (attempt / 8) as f64;
                at = Vector3::new(rad * phi.cos(), rad * phi.sin(), z);
                if self.near_top.iter().all(|x| (x - at).norm() > 1.05 * d) {
                    break;
                }
            }
            self.near_top.push(at);
            gone.push((k, at));
        }
        if gone.is_empty() {
            return Ok(0);
        }
        let old: Vec<BodyHandle> = gone.iter().map(|&(k, _)| self.handles[k]).collect();
        let removed = sys.remove_bodies(&old)?;
        for (&(k, at), body) in gone.iter().zip(&removed) {
            self.handles[k] = sys.add_body(like(body).position(at))?;
        }
        Ok(gone.len())
    }
}

/// A builder of a body like `body` (name, motion, mass, inertia, colliders), at rest at
/// the origin, unrotated.
fn like(body: &RigidBody) -> RigidBodyBuilder {
    let builder = match body.motion() {
        BodyMotion::Dynamic => RigidBodyBuilder::dynamic(),
        BodyMotion::Fixed => RigidBodyBuilder::fixed(),
        BodyMotion::Kinematic => RigidBodyBuilder::kinematic(),
    };
    let builder = (builder.name(body.name()))
        .mass(body.mass())
        .inertia(*body.inertia());
    (body.colliders().iter()).fold(builder, |b, c| {
        b.collider(c.shape.clone(), c.local_pose, c.material)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn annulus_hole_has_the_circle_area_and_faces_up() {
        let Shape::TriMesh { vertices, indices } = annulus(0.01, 0.05, 48) else {
            unreachable!()
        };
        // Area of the inner polygon from its vertices (every other one).
        let inner: Vec<_> = vertices.iter().step_by(2).collect();
        let mut area = 0.0;
        for k in 0..inner.len() {
            let (a, b) = (inner[k], inner[(k + 1) % inner.len()]);
            area += 0.5 * (a.x * b.y - b.x * a.y);
        }
        let circle = std::f64::consts::PI * 0.01 * 0.01;
        assert!(
            (area - circle).abs() < 1e-12 * circle.max(1.0),
            "{area} vs {circle}"
        );
        for t in &indices {
            let [a, b, c] = t.map(|i| vertices[i as usize]);
            assert!((b - a).cross(&(c - a)).z > 0.0);
        }
    }
}
