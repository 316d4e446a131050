//! A rigid wheel driven at fixed slip on MPM sand, in plane strain: the single-wheel test
//! of terramechanics (Wong, "Theory of Ground Vehicles", 4th ed., Wiley 2008, ch. 2).
//!
//! The wheel is a cylinder of radius `R` along `y` ([`crate::rigid::Shape::Cylinder`]) across the slab
//! of the soil bin ([`crate::soil_bin`]; a wheel of width `b` represented by a slab of
//! thickness `dx`, every force scaled by `b / dx`), in two-way frictional contact with the
//! sand: Coulomb slip at the grid nodes inside it ([`Contact::Slip`], friction
//! `tan(delta)`), with the rim's surface velocity `v + omega x (x - x_c)`
//! ([`RigidBody::velocity_at`]). Its spin `omega` (about `+y`, rolling towards `+x`) and
//! forward speed `v` are prescribed at a fixed slip
//!
//! ```text
//! s = 1 - v / (omega R),   omega R = U (the rim speed),   v = (1 - s) U
//! ```
//!
//! (`s` in `[-1, 1]`: 0 free rolling, 1 spinning in place, `-1` a braked wheel skidding at
//! twice its rim speed). Its height is free: the wheel of mass `M` carries the vertical
//! load `W` and the soil's reaction,
//!
//! ```text
//! M dv_z/dt = F_z - W,      F_z = -J_z / dt
//! ```
//!
//! with `J` the impulse the wheel gave the grid in the step ([`RigidBody::impulse`]); what
//! the wheel loses the grid gains, so wheel and soil together keep their vertical momentum
//! (tested). The run: the load ramps up over `load_time` with the wheel at rest (the static
//! sinkage), then `U` ramps up over `ramp_time` and the wheel drives on for
//! `rim_travel R` of rim travel; the steady values are the means over the last
//! `average_fraction` of the drive:
//!
//! - sinkage `z`: the rim's lowest point below the initial surface, m;
//! - drawbar pull `DP = F_x`, the soil's horizontal force on the wheel (towards `+x`
//!   positive: a net traction), N;
//! - driving torque `T = J_L,y / dt`, the torque about the axle the drive applies to hold
//!   `omega` against the soil (the angular impulse the rim gives the grid,
//!   [`RigidBody::angular_impulse`]), N m.
//!
//! The rim acts on the nodes inside it, and the B-spline carries a node's velocity to
//! markers up to `1.5 dx` away: the contact surface is smeared over about a cell, so the
//! sinkage is resolved to a fraction of `dx` (`docs/mpm.md`).

use nalgebra::Vector3;

use crate::body::MpmBody;
use crate::error::{Result, at_least, invalid, positive};
use crate::rigid::{Contact, RigidBody, speed_ramp};
use crate::soil_bin::{SoilSpec, surface};

/// Parameters of the wheel test.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WheelSpec {
    /// The sand.
    pub soil: SoilSpec,
    /// Wheel radius `R`, m.
    pub wheel_radius: f64,
    /// Wheel width `b`, m (the slab of thickness `dx` stands for it: forces scale by
    /// `b / dx`).
    pub wheel_width: f64,
    /// Vertical load `W` on the wheel, N.
    pub load: f64,
    /// Wheel mass `M`, kg; `None`: `W / g` (the load is the wheel's weight).
    pub wheel_mass: Option<f64>,
    /// Slip `s = 1 - v / (omega R)`, in `[-1, 1]`.
    pub slip: f64,
    /// Rim speed `U = omega R`, m/s.
    pub rim_speed: f64,
    /// Rim–soil friction angle `delta`, degrees, in [0, 90).
    pub wheel_friction_angle_deg: f64,
    /// Grid cells across the radius.
    pub cells_radius: usize,
    /// Nodes lighter than this fraction of an interior node's mass take no contact
    /// condition ([`RigidBody::min_node_mass`]; 0: all nodes with mass).
    pub contact_mass_fraction: f64,
    /// Soil depth, in radii.
    pub soil_depth: f64,
    /// Time over which the load ramps up (wheel at rest), s.
    pub load_time: f64,
    /// Time over which the rim speed ramps up, s.
    pub ramp_time: f64,
    /// Rim travel after the ramp, in radii.
    pub rim_travel: f64,
    /// The steady values are the means over this last fraction of the drive, in (0, 1].
    pub average_fraction: f64,
}

impl Default for WheelSpec {
    /// A laboratory wheel (`R` 0.25 m, `b` 0.15 m, 400 N) at 20 % slip on the default
    /// sand, 8 cells across `R`.
    fn default() -> Self {
        Self {
            soil: SoilSpec::default(),
            wheel_radius: 0.25,
            wheel_width: 0.15,
            load: 400.0,
            wheel_mass: None,
            slip: 0.2,
            rim_speed: 0.5,
            wheel_friction_angle_deg: 30.0,
            cells_radius: 8,
            contact_mass_fraction: 0.25,
            soil_depth: 1.5,
            load_time: 0.2,
            ramp_time: 0.1,
            rim_travel: 2.0,
            average_fraction: 0.4,
        }
    }
}

/// One sample of the wheel run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WheelSample {
    /// Time, s.
    pub t: f64,
    /// Forward travel of the axle, m.
    pub travel: f64,
    /// Sinkage, m.
    pub sinkage: f64,
    /// Drawbar pull over the sampling interval (full width), N.
    pub drawbar_pull: f64,
    /// Driving torque over the sampling interval (full width), N m.
    pub torque: f64,
    /// Vertical soil force over the sampling interval (full width), N.
    pub vertical_force: f64,
}

/// What a wheel run measured (full-width values).
#[derive(Clone, Debug)]
pub struct WheelResult {
    /// Sinkage at the end of the static loading, m.
    pub static_sinkage: f64,
    /// Mean sinkage over the steady window, m.
    pub sinkage: f64,
    /// Mean drawbar pull over the window, N.
    pub drawbar_pull: f64,
    /// Mean driving torque over the window, N m.
    pub torque: f64,
    /// Mean vertical soil force over the window (equals the load at steady state), N.
    pub vertical_force: f64,
    /// The samples (every 1/200 of the run).
    pub samples: Vec<WheelSample>,
    /// Steps taken.
    pub steps: u64,
}

/// The wheel on the soil bin.
#[derive(Clone, Debug)]
pub struct Wheel {
    /// The MPM body (the wheel is `body.rigid[0]`).
    pub body: MpmBody,
    spec: WheelSpec,
    /// `b / dx`: full-width forces per slab force, -.
    scale: f64,
    /// Slab mass of the wheel, kg.
    mass: f64,
    /// The initial surface height, m.
    top: f64,
    x0: f64,
}

impl Wheel {
    /// Builds the bin and the wheel resting on its surface; errors name the field
    /// (`wheel.*`, `soil.*`, `material.*`).
    pub fn new(spec: WheelSpec) -> Result<Self> {
        let r = positive("wheel.wheel_radius", spec.wheel_radius)?;
        let b = positive("wheel.wheel_width", spec.wheel_width)?;
        if !(spec.slip.is_finite() && (-1.0..=1.0).contains(&spec.slip)) {
            return Err(invalid("wheel.slip", spec.slip, "must lie in [-1, 1]"));
        }
        at_least("wheel.load", spec.load, 0.0, "must be finite and >= 0")?;
        let mass = match spec.wheel_mass {
            Some(m) => positive("wheel.wheel_mass", m)?,
            None => {
                if !(spec.load > 0.0 && spec.soil.gravity > 0.0) {
                    return Err(invalid(
                        "wheel.wheel_mass",
                        "None",
                        "must be given when the load or gravity is 0 (the mass is W / g)",
                    ));
                }
                spec.load / spec.soil.gravity
            }
        };
        positive("wheel.rim_speed", spec.rim_speed)?;
        let delta = spec.wheel_friction_angle_deg;
        if !(delta.is_finite() && (0.0..90.0).contains(&delta)) {
            return Err(invalid(
                "wheel.wheel_friction_angle_deg",
                delta,
                "must lie in [0, 90)",
            ));
        }
        if spec.cells_radius < 2 {
            return Err(invalid(
                "wheel.cells_radius",
                spec.cells_radius,
                "must be >= 2",
            ));
        }
        if !(spec.contact_mass_fraction.is_finite()
            && (0.0..=1.0).contains(&spec.contact_mass_fraction))
        {
            return Err(invalid(
                "wheel.contact_mass_fraction",
                spec.contact_mass_fraction,
                "must lie in [0, 1]",
            ));
        }
        at_least(
            "wheel.soil_depth",
            spec.soil_depth,
            0.5,
            "must be >= 0.5 (radii)",
        )?;
        for (name, v) in [
            ("wheel.load_time", spec.load_time),
            ("wheel.ramp_time", spec.ramp_time),
            ("wheel.rim_travel", spec.rim_travel),
        ] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(invalid(name, v, "must be finite and >= 0"));
            }
        }
        if !(spec.average_fraction > 0.0 && spec.average_fraction <= 1.0) {
            return Err(invalid(
                "wheel.average_fraction",
                spec.average_fraction,
                "must lie in (0, 1]",
            ));
        }
        let dx = r / spec.cells_radius as f64;
        // Room behind the wheel, its forward travel (the ramp's mean speed is half of U),
        // and the bulldozed zone ahead.
        let drive =
            (1.0 - spec.slip) * (0.5 * spec.ramp_time * spec.rim_speed + spec.rim_travel * r);
        let (behind, ahead) = (r, 2.0 * r);
        let depth = spec.soil_depth * r;
        let mut body = spec.soil.build(behind + drive + ahead, depth, r, dx)?;
        let top = surface(depth, dx);
        let mu = delta.to_radians().tan();
        body.rigid.push(RigidBody::new_cylinder(
            Vector3::new(behind, 0.5 * dx, top + r),
            r,
            2.0 * dx,
            Vector3::zeros(),
            Vector3::zeros(),
            Contact::Slip { friction: mu },
        )?);
        // Only nodes on or inside the material take the rim's condition: at least a
        // quarter of an interior node's mass, rho dx^3 / 2 in the slab (two node layers
        // across it); [`RigidBody::min_node_mass`].
        body.rigid[0].min_node_mass =
            spec.contact_mass_fraction * 0.5 * spec.soil.density * dx.powi(3);
        let scale = b / dx;
        Ok(Self {
            body,
            spec,
            scale,
            mass: mass / scale,
            top,
            x0: behind,
        })
    }

    /// The parameters.
    pub fn spec(&self) -> &WheelSpec {
        &self.spec
    }

    /// The rim's lowest point below the initial surface, m.
    pub fn sinkage(&self) -> f64 {
        self.top - (self.body.rigid[0].position.z - self.spec.wheel_radius)
    }

    /// The wheel's slab mass (the full mass times `dx / b`), kg.
    pub fn slab_mass(&self) -> f64 {
        self.mass
    }

    /// Full-width force per slab force, `b / dx`.
    pub fn scale(&self) -> f64 {
        self.scale
    }

    /// The drive's rim speed and the load's fraction at time `t` (s).
    fn schedule(&self, t: f64) -> (f64, f64) {
        let s = &self.spec;
        let load = speed_ramp(t, s.load_time);
        let u = if t < s.load_time {
            0.0
        } else {
            s.rim_speed * speed_ramp(t - s.load_time, s.ramp_time)
        };
        (u, load)
    }

    /// One step of `dt` (s): the drive set from the schedule at the step's start, the MPM
    /// step, then the wheel's vertical velocity from the soil's impulse and the load.
    pub fn step(&mut self, dt: f64) -> Result<()> {
        let (u, f) = self.schedule(self.body.time());
        let s = self.spec;
        let w = &mut self.body.rigid[0];
        w.velocity.x = (1.0 - s.slip) * u;
        w.angular_velocity = Vector3::new(0.0, u / s.wheel_radius, 0.0);
        self.body.step(dt)?;
        let load = s.load / self.scale * f;
        let w = &mut self.body.rigid[0];
        w.velocity.z += (-w.impulse.z - load * dt) / self.mass;
        Ok(())
    }

    /// The whole run (module documentation); `progress` gets the fraction of the time
    /// done. Errors: a diverging run, a marker leaving the grid (naming the marker and the
    /// step).
    pub fn run(&mut self, mut progress: impl FnMut(f64)) -> Result<WheelResult> {
        let s = self.spec;
        let t_load = s.load_time;
        let t_end = t_load + s.ramp_time + s.rim_travel * s.wheel_radius / s.rim_speed;
        let t_avg = t_end - s.average_fraction * (t_end - t_load - s.ramp_time);
        let every = t_end / 200.0;
        let mut samples = Vec::with_capacity(201);
        let mut static_sinkage = f64::NAN;
        let (mut t0, mut j0, mut l0) = (0.0, Vector3::zeros(), Vector3::zeros());
        let mut next = every;
        // Window sums: sinkage time integral, impulses at the window's start.
        let mut window: Option<(f64, Vector3<f64>, Vector3<f64>)> = None;
        let mut sink_int = 0.0;
        let mut k = 0u64;
        while self.body.time() < t_end {
            let dt = 0.999 * self.body.stable_dt();
            let before = self.sinkage();
            self.step(dt)?;
            k += 1;
            let t = self.body.time();
            let w = &self.body.rigid[0];
            if static_sinkage.is_nan() && t >= t_load {
                static_sinkage = self.sinkage();
            }
            if t >= t_avg {
                if window.is_none() {
                    window = Some((t, w.total_impulse, w.total_angular_impulse));
                } else {
                    sink_int += 0.5 * (before + self.sinkage()) * dt;
                }
            }
            if t >= next || t >= t_end {
                next += every;
                let span = t - t0;
                let j = (w.total_impulse - j0) / span * self.scale;
                let l = (w.total_angular_impulse - l0) / span * self.scale;
                samples.push(WheelSample {
                    t,
                    travel: w.position.x - self.x0,
                    sinkage: self.sinkage(),
                    drawbar_pull: -j.x,
                    torque: l.y,
                    vertical_force: -j.z,
                });
                (t0, j0, l0) = (t, w.total_impulse, w.total_angular_impulse);
            }
            if k.is_multiple_of(64) {
                progress(t / t_end);
            }
        }
        let w = &self.body.rigid[0];
        let t = self.body.time();
        let (ta, ja, la) = window.unwrap_or((t, w.total_impulse, w.total_angular_impulse));
        let span = t - ta;
        let (sinkage, j, l) = if span > 0.0 {
            (
                sink_int / span,
                (w.total_impulse - ja) / span * self.scale,
                (w.total_angular_impulse - la) / span * self.scale,
            )
        } else {
            (
                self.sinkage(),
                w.impulse / w.last_dt * self.scale,
                w.angular_impulse / w.last_dt * self.scale,
            )
        };
        Ok(WheelResult {
            static_sinkage,
            sinkage,
            drawbar_pull: -j.x,
            torque: l.y,
            vertical_force: -j.z,
            samples,
            steps: self.body.steps(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::body::MpmBody;
    use crate::grid::Wall;

    fn small() -> WheelSpec {
        WheelSpec {
            wheel_radius: 0.2,
            cells_radius: 4,
            soil_depth: 1.0,
            load: 200.0,
            rim_travel: 0.5,
            ..WheelSpec::default()
        }
    }

    #[test]
    fn bad_wheel_input_names_the_field() {
        let bad = |s: WheelSpec, field: &str| {
            let e = Wheel::new(s).unwrap_err();
            assert!(e.to_string().contains(field), "{e} should name {field}");
        };
        let d = small();
        bad(
            WheelSpec {
                wheel_radius: -0.2,
                ..d
            },
            "wheel.wheel_radius",
        );
        bad(WheelSpec { slip: 1.5, ..d }, "wheel.slip");
        bad(WheelSpec { slip: -1.01, ..d }, "wheel.slip");
        bad(
            WheelSpec {
                slip: f64::NAN,
                ..d
            },
            "wheel.slip",
        );
        bad(
            WheelSpec {
                wheel_width: 0.0,
                ..d
            },
            "wheel.wheel_width",
        );
        bad(WheelSpec { load: -1.0, ..d }, "wheel.load");
        bad(
            WheelSpec {
                wheel_friction_angle_deg: 90.0,
                ..d
            },
            "wheel.wheel_friction_angle_deg",
        );
        bad(
            WheelSpec {
                soil: SoilSpec {
                    young: -1.0,
                    ..d.soil
                },
                ..d
            },
            "material.young",
        );
    }

    #[test]
    fn contact_conserves_momentum_of_wheel_and_soil() {
        // A weightless soil and a free wheel of mass M driven into it at 0.3 m/s while
        // spinning at 30 % slip; the bin's walls opened (they would take momentum once the
        // disturbance reaches them). Vertical: the soil's momentum plus the wheel's stays
        // constant; horizontal (the drive holds v): the soil's momentum changes by the
        // wheel's impulse; angular (about y): by x_c x J + L per step.
        let spec = WheelSpec {
            soil: SoilSpec {
                gravity: 0.0,
                ..SoilSpec::default()
            },
            load: 0.0,
            wheel_mass: Some(5.0),
            slip: 0.3,
            load_time: 0.0,
            ramp_time: 0.0,
            ..small()
        };
        let mut w = Wheel::new(spec).unwrap();
        let gs = w
            .body
            .spec()
            .with_walls(0, Wall::Open, Wall::Open)
            .with_walls(2, Wall::Open, Wall::Open);
        let mut open = MpmBody::new(gs, *w.body.material(), *w.body.settings()).unwrap();
        open.markers = w.body.markers.clone();
        open.rigid = w.body.rigid.clone();
        w.body = open;
        let dx = w.body.spec().dx;
        w.body.rigid[0].position.z -= 0.5 * dx;
        w.body.rigid[0].velocity.z = -0.3;
        let m = w.slab_mass();
        let total_z = |w: &Wheel| w.body.momentum().z + m * w.body.rigid[0].velocity.z;
        let (pz0, p0, l0) = (total_z(&w), w.body.momentum(), w.body.angular_momentum());
        let mut moment = Vector3::zeros();
        for _ in 0..40 {
            let c = w.body.rigid[0].position;
            let dt = 0.9 * w.body.stable_dt();
            w.step(dt).unwrap();
            let r = &w.body.rigid[0];
            moment += c.cross(&r.impulse) + r.angular_impulse;
        }
        let r = &w.body.rigid[0];
        // The wheel did push and drag (real impulses, not zero = zero).
        assert!(
            r.total_impulse.z < -1e-3 && r.total_impulse.x.abs() > 1e-4,
            "{r:?}"
        );
        let scale = r.total_impulse.norm();
        let ez = (total_z(&w) - pz0).abs() / scale;
        assert!(ez < 1e-12, "vertical momentum error {ez:e}");
        let ex = (w.body.momentum().x - p0.x - r.total_impulse.x).abs() / scale;
        assert!(ex < 1e-12, "horizontal momentum error {ex:e}");
        let el = (w.body.angular_momentum().y - l0.y - moment.y).abs() / moment.norm();
        assert!(el < 1e-10, "angular momentum error {el:e}");
        assert!(r.total_angular_impulse.y.abs() > 0.0);
    }

    /// A wheel on nearly rigid ground: cohesive (100 kPa) and stiff (E 50 MPa) sand under
    /// which the 200 N load sinks the rim by well under a tenth of a cell.
    fn rigid_ground(slip: f64, cells: usize) -> (WheelResult, f64) {
        let mut w = Wheel::new(WheelSpec {
            soil: SoilSpec {
                young: 5e7,
                cohesion: 1e5,
                ..SoilSpec::default()
            },
            slip,
            cells_radius: cells,
            // The mean over several node crossings (the contact's bumps, a cell apart).
            rim_travel: 2.0,
            average_fraction: 0.75,
            ..small()
        })
        .unwrap();
        let r = w.run(|_| {}).unwrap();
        let dx = w.body.spec().dx;
        assert!(
            r.sinkage.abs() < 0.1 * dx,
            "sinkage {} m, dx {dx} m",
            r.sinkage
        );
        assert!(
            (r.vertical_force / 200.0 - 1.0).abs() < 0.12,
            "vertical force {} N against the load 200 N",
            r.vertical_force
        );
        let s = w.spec();
        (r, s.load * s.wheel_radius)
    }

    #[test]
    fn sliding_wheel_on_rigid_ground_pulls_and_needs_coulomb_friction() {
        // At 50 % slip on rigid ground the rim slides over the whole (point) contact:
        // Coulomb's law gives the traction mu W and the torque mu W R (mu = tan 30 deg,
        // the rim-soil friction).
        let (r, wr) = rigid_ground(0.5, 4);
        let mu = 30f64.to_radians().tan();
        let (dp, t) = (r.drawbar_pull / 200.0, r.torque / wr);
        assert!((dp / mu - 1.0).abs() < 0.03, "DP/W {dp} against mu {mu}");
        assert!((t / mu - 1.0).abs() < 0.03, "T/(W R) {t} against mu {mu}");
    }

    #[test]
    fn wheel_on_rigid_ground_rolls_free_within_one_percent_slip() {
        // On rigid ground the torque against slip is steep: the contact is a point (here
        // a few nodes), so a small creep already saturates the friction (Carter's rolling
        // contact: the saturating creep is of the order of mu a / R, a the contact
        // half-length; Johnson, Contact Mechanics, 1985, sec. 8.4). Free rolling, zero
        // torque, must lie between -1 % and +1 % slip: the torque changes sign there
        // (measured, docs/mpm.md: T/(W R) = -0.41, -0.18, +0.42 at -2 %, 0, +1 % slip).
        let (braked, wr) = rigid_ground(-0.01, 4);
        let (driven, _) = rigid_ground(0.01, 4);
        let (tb, td) = (braked.torque / wr, driven.torque / wr);
        assert!(
            tb < 0.0 && td > 0.0,
            "T/(W R): {tb} at -1 % slip, {td} at +1 %"
        );
    }
}
