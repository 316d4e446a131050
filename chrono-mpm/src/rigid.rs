//! Kinematic rigid bodies in the grid update: plates, strip footings (boxes) whose
//! velocity is prescribed, and the reaction force the material exerts on them.
//!
//! After the grid velocities `v_i` are formed (and the walls applied), every grid node `i`
//! of the box with mass whose position is inside or on the body (signed distance
//! `phi(x_i) <= 0`) takes the body's velocity as a contact condition
//! (Stomakhin et al., "A material point method for snow simulation", ACM TOG 32(4), 2013,
//! sec. 8, here with a moving body): with `v_rel = v_i - v_b` and `n` the body's outward
//! normal at the node (the gradient of `phi`),
//!
//! ```text
//! Sticky:           v_i' = 2 v_b - v(x_i + 2 a n)      (image; a = -phi(x_i) the depth)
//! Slip { mu }:      v_n = v_rel . n;  if v_n >= 0 (separating): v_i' = v_i
//!                   else v_t = v_rel - v_n n,
//!                        v_i' = v_b + v_t max(0, 1 + mu v_n / |v_t|)     (Coulomb)
//! ```
//!
//! `mu = 0` is a frictionless, unilateral contact; the normal velocity into the body is
//! removed and the tangential one reduced by `mu |v_n|` (the Coulomb bound on the
//! tangential impulse `mu` times the normal one, per node).
//!
//! The sticky contact is bilateral and takes the *mirror image* of the material's velocity
//! about the body's surface, as the grid's walls do ([`crate::grid::Wall`]): a node at depth
//! `a` inside the body gets `2 v_b - v(x_i + 2 a n)`, with `v` at the mirror point
//! interpolated along the normal between the surface (`v_b`) and the nodes outside (if
//! one has no mass, the node takes `v_b`). The interpolated field is then `v_b` *at the
//! surface* and a linear field is continued exactly through it. Setting `v_b` on every
//! node inside instead puts the effective surface up to a cell inside the body: a column
//! 8 cells high compressed by a plate came out 10 % softer than `lambda + 2 mu` that way,
//! 7.6 % with the image, 0.26 % with the image and the ghosts' mass and force folded into
//! the nodes it reads ([`crate::fold`]; 0.13 % at 16 cells; `docs/mpm.md`,
//! `plate_reaction_is_the_uniaxial_strain_modulus`).
//! The slip contact keeps the simple node condition (its error is first order in `dx`).
//! Opt-in for a sticky box, the ghosts' fold is replaced by mirrored markers
//! ([`RigidBody::mirrored_markers`]): the same sums for a face on a node plane, and no
//! dependence on where a face between node planes lies (the lumped fold's reading changes
//! as the face passes a half-node).
//!
//! **Reaction, sign convention.** The body changes the momentum of the grid by
//!
//! ```text
//! J = sum_i m_i (v_i' - v_i)        N s, per step
//! ```
//!
//! over the nodes it changes (those inside and, for a sticky body, the nodes its ghosts
//! are folded into, with the folded masses), the impulse the body gives the material
//! ([`RigidBody::impulse`]); the force the material exerts on the body is `-J / dt`
//! ([`RigidBody::force_on_body`]). Since the
//! transfers conserve momentum (P2G and G2P to round-off), the markers' momentum changes by
//! the sum of the bodies' impulses (and of the walls' and gravity's): tested to round-off
//! (`rigid_impulse_equals_the_material_momentum_change`).
//!
//! The body moves after each step by `velocity dt`; the caller may change `velocity`
//! between steps (a prescribed motion).

use nalgebra::Vector3;

use crate::error::{Result, invalid, positive};

/// The contact condition of a rigid body (see the module documentation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Contact {
    /// The material sticks: nodes inside the body take its velocity.
    Sticky,
    /// Unilateral contact with Coulomb friction coefficient `friction` (>= 0; 0 is
    /// frictionless slip).
    Slip {
        /// Coulomb friction coefficient, -.
        friction: f64,
    },
}

/// The shape of a rigid body, about its centre.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Shape {
    /// An axis-aligned box of the given half-extents, m.
    Box {
        /// Half-extents along x, y, z, m.
        half: [f64; 3],
    },
    /// A cylinder with its axis along y (a wheel rolling in the x-z plane), m.
    Cylinder {
        /// Radius, m.
        radius: f64,
        /// Half-length along y, m.
        half_length: f64,
    },
}

impl Shape {
    /// The signed distance of `x` (relative to the centre, m) and the outward unit normal
    /// (the gradient of the distance). Inside a box the normal is that of the nearest face
    /// (the lowest axis on a tie).
    pub fn distance(&self, x: &Vector3<f64>) -> (f64, Vector3<f64>) {
        match *self {
            Shape::Box { half } => {
                let q = Vector3::from_fn(|a, _| x[a].abs() - half[a]);
                let sign = |a: usize| if x[a] < 0.0 { -1.0 } else { 1.0 };
                if q.max() > 0.0 {
                    // Outside: distance to the nearest point of the box.
                    let out = q.map(|c| c.max(0.0));
                    let d = out.norm();
                    let n = Vector3::from_fn(|a, _| sign(a) * out[a] / d);
                    (d, n)
                } else {
                    let a = q.imax();
                    let mut n = Vector3::zeros();
                    n[a] = sign(a);
                    (q[a], n)
                }
            }
            Shape::Cylinder {
                radius,
                half_length,
            } => {
                // A box in (r, |y|): the radial distance and the distance past the caps.
                let r = (x.x * x.x + x.z * x.z).sqrt();
                let qr = r - radius;
                let qy = x.y.abs() - half_length;
                let radial = if r > 0.0 {
                    Vector3::new(x.x / r, 0.0, x.z / r)
                } else {
                    // On the axis every radial direction is as near: take -z (down).
                    -Vector3::z()
                };
                let axial = Vector3::new(0.0, if x.y < 0.0 { -1.0 } else { 1.0 }, 0.0);
                if qr > 0.0 || qy > 0.0 {
                    let (a, b) = (qr.max(0.0), qy.max(0.0));
                    let d = (a * a + b * b).sqrt();
                    (d, (radial * a + axial * b) / d)
                } else if qr >= qy {
                    (qr, radial)
                } else {
                    (qy, axial)
                }
            }
        }
    }

    /// A box containing the shape, half-extents about its centre, m.
    pub fn bounding_half(&self) -> [f64; 3] {
        match *self {
            Shape::Box { half } => half,
            Shape::Cylinder {
                radius,
                half_length,
            } => [radius, half_length, radius],
        }
    }
}

/// A kinematic rigid body: prescribed velocity, measured reaction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RigidBody {
    /// The shape.
    pub shape: Shape,
    /// Position of the centre, m.
    pub position: Vector3<f64>,
    /// Prescribed velocity of the centre, m/s (may be changed between steps).
    pub velocity: Vector3<f64>,
    /// Prescribed angular velocity about the centre, rad/s (may be changed between
    /// steps): the surface velocity at `x` is `velocity + angular_velocity x (x - position)`.
    /// Rotation moves the surface, not the shape (which must then be symmetric about the
    /// axis of rotation, as a wheel is about its axle).
    pub angular_velocity: Vector3<f64>,
    /// The contact condition.
    pub contact: Contact,
    /// Nodes lighter than this take no contact condition, kg (0: every node with mass).
    /// A node that only the tail of the markers' splines reaches lies outside the
    /// material (a flat surface through a node row gives the row half an interior node's
    /// mass and the row above it 1/32 of it, with two markers per cell): constraining it
    /// puts the contact up to a cell outside the material, which a rolling wheel then
    /// climbs (`crate::wheel`).
    pub min_node_mass: f64,
    /// The impulse the body gave the material in the last step, `sum_i m_i (v_i' - v_i)`,
    /// N s.
    pub impulse: Vector3<f64>,
    /// The sum of [`RigidBody::impulse`] over all steps, N s.
    pub total_impulse: Vector3<f64>,
    /// The angular impulse the body gave the material in the last step about its centre,
    /// `sum_i (x_i - x_c) x m_i (v_i' - v_i)`, N m s (the torque the body's drive applies
    /// times `dt`).
    pub angular_impulse: Vector3<f64>,
    /// The sum of [`RigidBody::angular_impulse`] over all steps, N m s.
    pub total_angular_impulse: Vector3<f64>,
    /// The length of the last step, s.
    pub last_dt: f64,
    /// The sticky image's boundary treatment from *mirrored markers* instead of the lumped
    /// fold (opt-in, off by default; a sticky, non-spinning box only:
    /// [`RigidBody::set_mirrored_markers`]). Each marker within `1.5 dx` of a face of the
    /// body (its nearest feature a face, not an edge or corner) adds to the grid, in P2G,
    /// the mass, momentum and stress of its mirror image about that face: with `R` the
    /// reflection about the face's plane (`R = I - 2 n n^T`, `n` the face's normal),
    ///
    /// ```text
    /// x' = x - 2 phi n,   m' = m,   v' = 2 v_b - v - dt g,   C' = -C R,   tau' = -tau R
    /// ```
    ///
    /// (`phi` the marker's signed distance to the face): the odd continuation of the
    /// velocity relative to the body (`v'(x') = 2 v_b - v(R x')`), the same images the
    /// sticky walls' fold gives for a face on a node plane ([`crate::fold`]: there the two
    /// are the same sums). The nodes outside the body then solve `v = p / m` with the
    /// mirrored markers' share; the nodes inside take the sticky image
    /// ([`crate::rigid`]); no ghost is folded. For a face between node planes the lumped
    /// fold reads the wrong nodes once the face passes a half-node (the top marker of a
    /// compressed column runs into the plate); the mirrored markers do not depend on where
    /// the face lies between nodes (`docs/mpm.md`, `mpm-snow`, "The plate's ghosts from
    /// mirrored markers"). The body's impulse is then the momentum change of the real
    /// markers' share of the nodes within `3 dx` of it (those its mirrored markers reach,
    /// `1.5 dx` beyond the mirror of a marker up to `1.5 dx` inside; the folded real masses):
    /// `J = sum_i m_i^r (v_i' - v_i^r)`, with `v_i^r` the node's velocity from the real
    /// markers alone under the walls' conditions.
    pub mirrored_markers: bool,
}

impl RigidBody {
    /// A box of half-extents `half` (m) centred at `position` (m) moving at `velocity`
    /// (m/s). Errors name the field (`rigid.half[a]`, `rigid.position`, `rigid.velocity`,
    /// `rigid.friction`).
    pub fn new_box(
        position: Vector3<f64>,
        half: [f64; 3],
        velocity: Vector3<f64>,
        contact: Contact,
    ) -> Result<Self> {
        for (a, h) in half.iter().enumerate() {
            positive(&format!("rigid.half[{a}]"), *h)?;
        }
        if !position.iter().all(|c| c.is_finite()) {
            return Err(invalid(
                "rigid.position",
                format!("{position:?}"),
                "must be finite",
            ));
        }
        if !velocity.iter().all(|c| c.is_finite()) {
            return Err(invalid(
                "rigid.velocity",
                format!("{velocity:?}"),
                "must be finite",
            ));
        }
        if let Contact::Slip { friction } = contact
            && !(friction.is_finite() && friction >= 0.0)
        {
            return Err(invalid(
                "rigid.friction",
                friction,
                "must be finite and >= 0",
            ));
        }
        Ok(Self {
            shape: Shape::Box { half },
            position,
            velocity,
            angular_velocity: Vector3::zeros(),
            contact,
            min_node_mass: 0.0,
            impulse: Vector3::zeros(),
            total_impulse: Vector3::zeros(),
            angular_impulse: Vector3::zeros(),
            total_angular_impulse: Vector3::zeros(),
            last_dt: 0.0,
            mirrored_markers: false,
        })
    }

    /// A cylinder (a wheel) of `radius` (m) and `half_length` (m) along y, centred at
    /// `position` (m), moving at `velocity` (m/s) and spinning at `angular_velocity`
    /// (rad/s). A sticky cylinder takes its surface velocity on the nodes inside (no
    /// image: [`RigidBody::uses_image`]). Errors name the field (`rigid.radius`,
    /// `rigid.half_length`, `rigid.position`, `rigid.velocity`, `rigid.angular_velocity`,
    /// `rigid.friction`).
    pub fn new_cylinder(
        position: Vector3<f64>,
        radius: f64,
        half_length: f64,
        velocity: Vector3<f64>,
        angular_velocity: Vector3<f64>,
        contact: Contact,
    ) -> Result<Self> {
        positive("rigid.radius", radius)?;
        positive("rigid.half_length", half_length)?;
        if !angular_velocity.iter().all(|c| c.is_finite()) {
            return Err(invalid(
                "rigid.angular_velocity",
                format!("{angular_velocity:?}"),
                "must be finite",
            ));
        }
        let mut r = Self::new_box(position, [radius, half_length, radius], velocity, contact)?;
        r.shape = Shape::Cylinder {
            radius,
            half_length,
        };
        r.angular_velocity = angular_velocity;
        Ok(r)
    }

    /// The surface velocity at `x` (m), `velocity + angular_velocity x (x - position)`,
    /// m/s.
    #[inline]
    pub fn velocity_at(&self, x: &Vector3<f64>) -> Vector3<f64> {
        self.velocity + self.angular_velocity.cross(&(x - self.position))
    }

    /// Whether a sticky body takes the mirror image ([`crate::rigid`]): a box that does
    /// not spin (its normals are grid axes and its surface velocity uniform). Other sticky
    /// bodies set their surface velocity on the nodes inside.
    pub fn uses_image(&self) -> bool {
        self.contact == Contact::Sticky
            && matches!(self.shape, Shape::Box { .. })
            && self.angular_velocity == Vector3::zeros()
    }

    /// Switches the boundary treatment from mirrored markers ([`RigidBody::mirrored_markers`])
    /// on or off. Errors name `rigid.mirrored_markers` for a body that does not take the
    /// sticky image ([`RigidBody::uses_image`]: slip contact, a cylinder, a spinning box).
    pub fn set_mirrored_markers(&mut self, on: bool) -> Result<()> {
        if on && !self.uses_image() {
            return Err(invalid(
                "rigid.mirrored_markers",
                on,
                "needs a sticky, non-spinning box (a body that takes the sticky image)",
            ));
        }
        self.mirrored_markers = on;
        Ok(())
    }

    /// Whether the body's boundary is from mirrored markers ([`RigidBody::mirrored_markers`]).
    #[inline]
    pub(crate) fn mirrors(&self) -> bool {
        self.mirrored_markers && self.uses_image()
    }

    /// The mirror image of a marker at `x` (m) about the body's nearest face, and the
    /// face's outward normal, if the marker lies within `reach` (m) of the face on either
    /// side and its nearest feature is a face (outside: one coordinate past the box; an
    /// edge's or corner's neighbours are not mirrored). `x' = x - 2 phi n`.
    pub(crate) fn mirror_marker(
        &self,
        x: &Vector3<f64>,
        reach: f64,
    ) -> Option<(Vector3<f64>, Vector3<f64>)> {
        let (phi, n) = self.shape.distance(&(x - self.position));
        if phi.abs() >= reach {
            return None;
        }
        if n.iter().filter(|c| **c != 0.0).count() != 1 {
            return None;
        }
        Some((x - n * (2.0 * phi), n))
    }

    /// The torque the material exerted on the body about its centre over the last step,
    /// `-angular_impulse / dt`, N m (zero before the first step).
    pub fn torque_on_body(&self) -> Vector3<f64> {
        if self.last_dt > 0.0 {
            -self.angular_impulse / self.last_dt
        } else {
            Vector3::zeros()
        }
    }

    /// The force the material exerted on the body over the last step, `-impulse / dt`, N
    /// (zero before the first step).
    pub fn force_on_body(&self) -> Vector3<f64> {
        if self.last_dt > 0.0 {
            -self.impulse / self.last_dt
        } else {
            Vector3::zeros()
        }
    }

    /// Checks the public fields (before a step); errors name the field.
    pub(crate) fn check(&self, k: usize) -> Result<()> {
        let bad = |what: &str, v: String| {
            Err(invalid(&format!("rigid[{k}].{what}"), v, "must be finite"))
        };
        if !self.position.iter().all(|c| c.is_finite()) {
            return bad("position", format!("{:?}", self.position));
        }
        if !self.velocity.iter().all(|c| c.is_finite()) {
            return bad("velocity", format!("{:?}", self.velocity));
        }
        if !self.angular_velocity.iter().all(|c| c.is_finite()) {
            return bad("angular_velocity", format!("{:?}", self.angular_velocity));
        }
        if self.mirrored_markers && !self.uses_image() {
            return Err(invalid(
                &format!("rigid[{k}].mirrored_markers"),
                true,
                "needs a sticky, non-spinning box (a body that takes the sticky image)",
            ));
        }
        Ok(())
    }

    /// The node velocity `v` after the contact condition, for the node `i` of the box at
    /// `x` (m), grid spacing `dx`; `node(j)` gives the velocity (after the walls) of node `j`
    /// if it has mass. `None` when the node is outside the body.
    #[inline]
    pub(crate) fn contact_velocity(
        &self,
        x: &Vector3<f64>,
        i: [i64; 3],
        dx: f64,
        v: [f64; 3],
        node: impl Fn([i64; 3]) -> Option<[f64; 3]>,
    ) -> Option<[f64; 3]> {
        let (phi, n) = self.shape.distance(&(x - self.position));
        if phi > 0.0 {
            return None;
        }
        let vb = self.velocity_at(x);
        match self.contact {
            Contact::Sticky if !self.uses_image() => Some(vb.into()),
            Contact::Sticky => Some(
                self.sticky_image(x, i, dx, -phi, &n, node)
                    .unwrap_or(vb)
                    .into(),
            ),
            Contact::Slip { friction } => {
                let rel = Vector3::from(v) - vb;
                let vn = rel.dot(&n);
                if vn >= 0.0 {
                    return Some(v);
                }
                let vt = rel - n * vn;
                let t = vt.norm();
                let scale = if t > 0.0 {
                    (1.0 + friction * vn / t).max(0.0)
                } else {
                    0.0
                };
                Some((vb + vt * scale).into())
            }
        }
    }

    /// The sticky image: a node at depth `a` (m) inside the body takes
    /// `2 v_b - v(x + 2 a n)`, the image of the velocity at the mirror point outside, with
    /// `v` interpolated linearly along the normal through the surface point (where it is
    /// `v_b`) and the nodes outside (`None` when one is missing: no material there). The
    /// interpolation weights are convex, so the image amplifies nothing. Box normals are
    /// grid axes, so the line's points are nodes.
    fn sticky_image(
        &self,
        x: &Vector3<f64>,
        i: [i64; 3],
        dx: f64,
        a: f64,
        n: &Vector3<f64>,
        node: impl Fn([i64; 3]) -> Option<[f64; 3]>,
    ) -> Option<Vector3<f64>> {
        let vb = self.velocity;
        let m = self.mirror(x, i, dx, a, n)?;
        // 2 v_b - ((1 - W) v_b + sum_k w_k v_k) = v_b - sum_k w_k (v_k - v_b).
        let mut v = vb;
        for k in 0..m.count {
            v -= (Vector3::from(node(m.nodes[k])?) - vb) * m.weights[k];
        }
        Some(v)
    }

    /// The mirror point of a node at `x` (index `i`) at depth `a` (m) inside the body,
    /// `x + 2 a n`, as an interpolation `v(mirror) = (1 - W) v_b + sum_k w_k v_k` between
    /// the surface point (`v_b`) and the (up to two) nodes outside on the normal line,
    /// `W = sum_k w_k`. `None` when the mirror point is not reached (a node deeper than the
    /// search); no nodes when the node is on the surface.
    pub(crate) fn mirror(
        &self,
        x: &Vector3<f64>,
        i: [i64; 3],
        dx: f64,
        a: f64,
        n: &Vector3<f64>,
    ) -> Option<Mirror> {
        let mut m = Mirror {
            nodes: [[0; 3]; 2],
            weights: [0.0; 2],
            count: 0,
        };
        if a <= 0.0 {
            return Some(m);
        }
        let axis = n.iamax();
        let step = if n[axis] > 0.0 { 1 } else { -1 };
        let mut h0 = 0.0;
        let mut j0: Option<[i64; 3]> = None;
        // The mirror point is at most `a` beyond the surface: a few nodes suffice.
        for k in 1..=(a / dx).ceil() as i64 + 2 {
            let xk = x + n * (k as f64 * dx);
            let (h, _) = self.shape.distance(&(xk - self.position));
            if h <= 0.0 {
                continue;
            }
            let mut j = i;
            j[axis] += step * k;
            if a <= h {
                let t = (a - h0) / (h - h0);
                match j0 {
                    None => {
                        m.nodes[0] = j;
                        m.weights[0] = t;
                        m.count = 1;
                    }
                    Some(jp) => {
                        m.nodes = [jp, j];
                        m.weights = [1.0 - t, t];
                        m.count = 2;
                    }
                }
                return Some(m);
            }
            (h0, j0) = (h, Some(j));
        }
        None
    }
}

/// The interpolation of a sticky image's mirror point ([`RigidBody::mirror`]): node
/// indices of the box and weights, the first `count` used.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Mirror {
    pub nodes: [[i64; 3]; 2],
    pub weights: [f64; 2],
    pub count: usize,
}

/// The smooth start of a prescribed speed: `(1 - cos(pi t / t_r)) / 2` for `t < t_r`, then
/// 1 (no velocity jump, so no stress wave from the start).
pub fn speed_ramp(t: f64, ramp_time: f64) -> f64 {
    if t < ramp_time {
        0.5 * (1.0 - (std::f64::consts::PI * t / ramp_time).cos())
    } else {
        1.0
    }
}

/// One sample of [`push_down`]: the means over a sampling interval.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct PushSample {
    /// Time at the middle of the interval, s.
    pub t: f64,
    /// The progress measure at the middle of the interval.
    pub measure: f64,
    /// Mean downward force on the body over the interval over `area`, Pa: minus the
    /// z-impulse it gave the material per time (the material takes momentum -z from it).
    pub pressure: f64,
    /// Kinetic energy of the markers at the end of the interval, J.
    pub kinetic: f64,
    /// Elastic energy of the markers at the end of the interval, J.
    pub elastic: f64,
    /// Work done by the body on the material since the start, J.
    pub work: f64,
}

/// Push `body.rigid[0]` down at `speed(t)` (m/s, downwards positive, set at each step's
/// start time; steps of 0.999 of the stable one) until `measure(body)` reaches `last`;
/// `samples` samples (at least 1), each when the measure passes the next of `samples`
/// equal fractions of `last`; `progress` gets the fraction done every 64 steps. The
/// shared driver of the compaction plate and the footing.
pub(crate) fn push_down(
    body: &mut crate::body::MpmBody,
    area: f64,
    last: f64,
    samples: usize,
    measure: impl Fn(&crate::body::MpmBody) -> f64,
    speed: impl Fn(f64) -> f64,
    mut progress: impl FnMut(f64),
) -> Result<Vec<PushSample>> {
    let samples = samples.max(1);
    let mut out = Vec::with_capacity(samples);
    let mut next = 1;
    let (mut t0, mut m0, mut j0) = (body.time(), measure(body), 0.0);
    let mut work = 0.0;
    let mut k = 0u64;
    while measure(body) < last {
        let v = speed(body.time());
        body.rigid[0].velocity = Vector3::new(0.0, 0.0, -v);
        let dt = 0.999 * body.stable_dt();
        body.step(dt)?;
        // The body's work on the material: the impulse it gives times its velocity.
        work += body.rigid[0].impulse.z * -v;
        k += 1;
        let m = measure(body);
        if m >= last * next as f64 / samples as f64 || m >= last {
            let t1 = body.time();
            let j1 = body.rigid[0].total_impulse.z;
            out.push(PushSample {
                t: 0.5 * (t0 + t1),
                measure: 0.5 * (m0 + m),
                pressure: -(j1 - j0) / (t1 - t0) / area,
                kinetic: body.kinetic_energy(),
                elastic: body.elastic_energy(),
                work,
            });
            (t0, m0, j0) = (t1, m, j1);
            while last * next as f64 / samples as f64 <= m {
                next += 1;
            }
        }
        if k.is_multiple_of(64) {
            progress((m / last).min(1.0));
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn box_distance_and_normal() {
        let s = Shape::Box {
            half: [1.0, 2.0, 0.5],
        };
        let (d, n) = s.distance(&Vector3::new(0.0, 0.0, 0.75));
        assert!((d - 0.25).abs() < 1e-15 && n == Vector3::z());
        let (d, n) = s.distance(&Vector3::new(0.5, 0.0, -0.3));
        assert!((d + 0.2).abs() < 1e-15 && n == -Vector3::z(), "{d} {n}");
        let (d, n) = s.distance(&Vector3::new(-0.9, 0.0, 0.0));
        assert!((d + 0.1).abs() < 1e-15 && n == -Vector3::x());
        let (d, _) = s.distance(&Vector3::new(4.0, 6.0, 0.0));
        assert!((d - 5.0).abs() < 1e-15);
    }

    const I: [i64; 3] = [0, 0, 1];
    fn none(_: [i64; 3]) -> Option<[f64; 3]> {
        None
    }

    #[test]
    fn contact_conditions() {
        let slip = |mu| {
            RigidBody::new_box(
                Vector3::zeros(),
                [1.0; 3],
                Vector3::new(0.0, 0.0, -1.0),
                Contact::Slip { friction: mu },
            )
            .unwrap()
        };
        // A node on the top face moving down at 3 m/s and sideways at 1 m/s, against the
        // body moving down at 1 m/s: v_n = -2.
        let x = Vector3::new(0.0, 0.0, 1.0);
        let v = [1.0, 0.0, -3.0];
        assert_eq!(
            slip(0.0).contact_velocity(&x, I, 1.0, v, none),
            Some([1.0, 0.0, -1.0])
        );
        // mu |v_n| = 0.25 * 2 = 0.5 off the tangential 1 m/s.
        assert_eq!(
            slip(0.25).contact_velocity(&x, I, 1.0, v, none),
            Some([0.5, 0.0, -1.0])
        );
        assert_eq!(
            slip(1.0).contact_velocity(&x, I, 1.0, v, none),
            Some([0.0, 0.0, -1.0])
        );
        // Separating: unchanged.
        assert_eq!(
            slip(1.0).contact_velocity(&x, I, 1.0, [1.0, 0.0, 0.5], none),
            Some([1.0, 0.0, 0.5])
        );
        // Outside: no condition.
        assert_eq!(
            slip(1.0).contact_velocity(&Vector3::new(0.0, 0.0, 1.01), I, 1.0, v, none),
            None
        );
        let sticky = RigidBody {
            contact: Contact::Sticky,
            ..slip(0.0)
        };
        assert_eq!(
            sticky.contact_velocity(&x, I, 1.0, v, none),
            Some([0.0, 0.0, -1.0])
        );
    }

    #[test]
    fn sticky_image_continues_a_linear_field() {
        // A body at rest with its top face at z = 1; outside, v = c (z - 1) (zero on the
        // surface). A node 0.3 m deep, nodes 0.5 m apart: the image is the linear field's
        // value there, -0.3 c, from the nodes at heights 0.2 and 0.7 above the surface.
        let body = RigidBody::new_box(
            Vector3::zeros(),
            [5.0, 5.0, 1.0],
            Vector3::zeros(),
            Contact::Sticky,
        )
        .unwrap();
        let c = [0.4, -0.2, 1.0];
        let x = Vector3::new(0.0, 0.0, 0.7);
        let field = |j: [i64; 3]| -> Option<[f64; 3]> {
            let z = 0.7 + 0.5 * (j[2] - I[2]) as f64;
            Some(c.map(|ci| ci * (z - 1.0)))
        };
        let v = body.contact_velocity(&x, I, 0.5, [9.0; 3], field).unwrap();
        for a in 0..3 {
            assert!((v[a] + 0.3 * c[a]).abs() < 1e-14, "{v:?}");
        }
        // Moving body: the image of the relative velocity.
        let moving = RigidBody {
            velocity: Vector3::new(0.0, 0.0, -2.0),
            ..body
        };
        let shifted = |j: [i64; 3]| field(j).map(|u| [u[0], u[1], u[2] - 2.0]);
        let v = moving
            .contact_velocity(&x, I, 0.5, [9.0; 3], shifted)
            .unwrap();
        assert!((v[2] - (-2.0 - 0.3 * c[2])).abs() < 1e-14, "{v:?}");
        // No material outside: the body's velocity.
        let v = moving.contact_velocity(&x, I, 0.5, [9.0; 3], none).unwrap();
        assert_eq!(v, [0.0, 0.0, -2.0]);
    }

    #[test]
    fn bad_rigid_input_names_the_field() {
        let e = RigidBody::new_box(
            Vector3::zeros(),
            [1.0, -1.0, 1.0],
            Vector3::zeros(),
            Contact::Sticky,
        )
        .unwrap_err();
        assert!(e.to_string().contains("rigid.half[1]"), "{e}");
        let e = RigidBody::new_box(
            Vector3::zeros(),
            [1.0; 3],
            Vector3::new(f64::NAN, 0.0, 0.0),
            Contact::Sticky,
        )
        .unwrap_err();
        assert!(e.to_string().contains("rigid.velocity"), "{e}");
        let e = RigidBody::new_box(
            Vector3::zeros(),
            [1.0; 3],
            Vector3::zeros(),
            Contact::Slip { friction: -0.1 },
        )
        .unwrap_err();
        assert!(e.to_string().contains("rigid.friction"), "{e}");
    }
}
