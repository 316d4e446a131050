//! One track's running gear in a system.
//!
//! | part | body and joint | contact |
//! |---|---|---|
//! | sprocket | revolute motor to the chassis about Y ([`TrackAssembly::set_sprocket_drive`]: free, held or driven) | two gear rings at `±gear_offset`: a pin seat (cylinder of radius `pitch_radius - pin_radius`) and `num_teeth` convex teeth each |
//! | idler | wheel on a revolute joint in a carrier; the carrier on a slide along X (a linear actuator without a drive; held by [`TrackAssembly::lock_adjuster`] for a grease adjuster); the tensioner a preloaded spring-damper pushing it rearward, the slide's implicit [`AxisSpring`] | cylinder |
//! | road wheel | wheel on a revolute joint in a trailing arm; the arm on a revolute joint to the chassis (a rotational motor without a drive, with angle limits where `arm_travel` gives stops) whose implicit [`AxisSpring`] is the torsion bar (plus the rotary shock's damping where fitted) | cylinder |
//! | roller | revolute joint to the chassis | cylinder |
//! | shoe | box plate; revolute joints about Y at the pins to its neighbours; the loop closes by two distance rows (the pin in the track plane), so no row repeats another | the plate (against wheels and ground) and two pin ends (cylinders at the front pin, in the gear rings' planes) |
//!
//! The shoes are laid out by [`super::geometry::layout`]; the idler starts where that puts
//! it and the tensioner's spring is at its preload there. Shoes and wheels start touching
//! (zero gap), so nothing jumps at the first step.
//!
//! The torsion bars, shocks and tensioner are spring-dampers on their joints' axes
//! ([`AxisSpring`]: backward Euler, a compliant row of the step), not explicit force
//! elements: an explicit spring-damper diverges once `2 c h / I + k h^2 / I` passes 4 on
//! a body the contacts leave free, and the M113's rear arm (`c` = 2,500 N m s/rad, `k` =
//! 2.5e4 N m/rad on about 4.5 kg m^2 about its pivot) passes it at `h` = 3.5 ms
//! (docs/validation-vehicle.md, "M113 at 5 ms").

use std::f64::consts::TAU;

use chrono_core::math::{Isometry3, Point3, UnitQuaternion, Vector3};
use chrono_core::{
    AxisSpring, BodyHandle, Drive, JointBuilder, JointHandle, JointKind, RigidBodyBuilder, Shape,
    System,
};

use crate::error::{Result, VehicleError};
use crate::suspension::MassData;

use super::TrackData;
use super::geometry::{ChainLayout, layout};

/// Convex slices of a sprocket tooth between the seat and the tip radius (its concave
/// flanks as chords).
const TOOTH_SLICES: usize = 4;

/// A road wheel and its suspension.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RoadWheel {
    /// The wheel.
    pub wheel: BodyHandle,
    /// The trailing arm.
    pub arm: BodyHandle,
    /// The arm's joint to the chassis; its [`AxisSpring`] is the torsion bar (with the
    /// shock's damping where fitted).
    pub arm_joint: JointHandle,
}

/// One side's running gear (see the [module docs](self)).
#[derive(Debug, Clone, PartialEq)]
pub struct TrackAssembly {
    /// 0 left, 1 right.
    pub side: usize,
    /// The sprocket.
    pub sprocket: BodyHandle,
    /// Its joint to the chassis (a rotational motor about Y).
    pub sprocket_joint: JointHandle,
    /// The idler wheel.
    pub idler: BodyHandle,
    /// The idler's carrier (slides along X).
    pub carrier: BodyHandle,
    /// The carrier's slide on the chassis (a linear actuator along X: free, or locked by
    /// [`TrackAssembly::lock_adjuster`]); its [`AxisSpring`] is the tensioner's
    /// spring-damper.
    pub tensioner_slide: JointHandle,
    /// The chassis the running gear hangs on.
    pub chassis: BodyHandle,
    /// The carrier's X in the chassis frame at assembly, m.
    carrier_x0: f64,
    /// The road wheels, front to rear.
    pub road_wheels: Vec<RoadWheel>,
    /// The support rollers.
    pub rollers: Vec<BodyHandle>,
    /// The shoes in chain order.
    pub shoes: Vec<BodyHandle>,
    /// The pin joints: `pins[k]` joins shoe `k - 1` and shoe `k` by a revolute joint for
    /// `k >= 1`; `pins[0]` is `closure[0]`.
    pub pins: Vec<JointHandle>,
    /// The loop's closure between the last shoe and the first: two distance joints (see
    /// [`TrackAssembly::build`]).
    pub closure: [JointHandle; 2],
    /// The assembled layout (pin positions in the track frame, idler offset, closure).
    pub layout: ChainLayout,
}

impl TrackAssembly {
    /// Build side `side` (0 left at `+track_y`, 1 right at `-track_y`) of `data` (validated
    /// by the caller) into `sys`, with its track frame at `frame` (the chassis reference pose
    /// shifted to the track's mid-plane; rotation = the chassis').
    pub fn build(
        sys: &mut System,
        data: &TrackData,
        side: usize,
        chassis: BodyHandle,
        frame: &Isometry3<f64>,
    ) -> Result<Self> {
        let shoes_n = data.shoe.count[side];
        let lay = layout(data, shoes_n, side)?;
        let name = ["track.left", "track.right"][side];
        let label = |part: &str| format!("{name}.{part}");
        let w = |p: [f64; 2]| -> Vector3<f64> {
            frame.transform_point(&Point3::new(p[0], 0.0, p[1])).coords
        };
        let rot = frame.rotation;
        let y_axis = rot * Vector3::y();
        let x_axis = rot * Vector3::x();
        let (mat_shoe, mat_wheel, mat_sprocket) = (
            data.materials.shoe,
            data.materials.wheel,
            data.materials.sprocket,
        );
        let dynamic = |part: &str, m: &MassData, at: Vector3<f64>, q: UnitQuaternion<f64>| {
            RigidBodyBuilder::dynamic()
                .name(label(part))
                .mass(m.mass)
                .inertia_diagonal(m.inertia_vector())
                .position(at)
                .rotation(q)
        };
        let cylinder = |radius: f64, width: f64| Shape::Cylinder {
            half_length: 0.5 * width,
            radius,
        };
        let revolute = |sys: &mut System, part: &str, a, b, at: Vector3<f64>| {
            sys.add_joint(
                JointBuilder::at_axis(JointKind::Revolute, a, b, at, y_axis).name(label(part)),
            )
        };

        // Rollers must stay below the upper run (checked before anything is built).
        for (k, ro) in data.rollers.iter().enumerate() {
            let clear = ro.radius + 0.5 * data.shoe.thickness;
            let n = lay.pins.len();
            for j in 0..n {
                let d = segment_distance(ro.location, lay.pins[j], lay.pins[(j + 1) % n]);
                if d < clear - 1e-6 {
                    return Err(VehicleError::invalid(
                        format!("track.rollers[{k}].location"),
                        format!("{:?}", ro.location),
                        format!(
                            "the roller reaches {:.4} m into shoe {j} of the assembled chain",
                            clear - d
                        ),
                    ));
                }
            }
        }

        // Sprocket: gear rings with the pin seat and the teeth.
        let s = &data.sprocket;
        let tau = TAU / s.num_teeth as f64;
        let seat = s.pitch_radius - data.shoe.pin_radius;
        // Each tooth is what two neighbouring troughs leave of the disc of the tip radius
        // (`SprocketData::gap_radius`): its flanks are concave arcs, so it is built from
        // `TOOTH_SLICES` convex slices between radii from just inside the seat to the tip,
        // each the hull of its corners (the arcs become chords).
        let root = 0.8 * seat;
        let radii: Vec<f64> = std::iter::once(root)
            .chain(
                (0..=TOOTH_SLICES)
                    .map(|j| seat + (s.tip_radius - seat) * j as f64 / TOOTH_SLICES as f64),
            )
            .collect();
        let half_width = |r: f64| 0.5 * tau - s.gap_half_angle(seat, r);
        let mut sb = dynamic("sprocket", &s.mass, w(s.location), rot);
        for ring in [-1.0, 1.0] {
            let yc = ring * s.gear_offset;
            sb = sb.collider(
                cylinder(seat, s.gear_width),
                Isometry3::translation(0.0, yc, 0.0),
                mat_sprocket,
            );
            for k in 0..s.num_teeth {
                let phi = lay.sprocket_start_angle - (k as f64 + 0.5) * tau;
                for pair in radii.windows(2) {
                    let mut pts = Vec::with_capacity(8);
                    for y in [yc - 0.5 * s.gear_width, yc + 0.5 * s.gear_width] {
                        for &r in pair {
                            // Below the seat the tooth keeps its width at the seat.
                            let a = half_width(r.max(seat));
                            for sg in [-1.0, 1.0] {
                                let t = phi + sg * a;
                                pts.push(Vector3::new(r * t.cos(), y, r * t.sin()));
                            }
                        }
                    }
                    sb = sb.collider(
                        Shape::ConvexHull { points: pts },
                        Isometry3::identity(),
                        mat_sprocket,
                    );
                }
            }
        }
        let sprocket = sys.add_body(sb)?;
        let sprocket_joint = sys.add_joint(
            JointBuilder::at_axis(
                JointKind::RotationalMotor {
                    drive: Drive::Effort(0.0),
                    max_torque: f64::INFINITY,
                    limits: None,
                },
                chassis,
                sprocket,
                w(s.location),
                y_axis,
            )
            .name(label("sprocket_joint")),
        )?;

        // Idler on its carrier and tensioner.
        let i = &data.idler;
        let ic = w([i.location[0] + lay.idler_offset, i.location[1]]);
        let carrier = sys.add_body(dynamic("idler_carrier", &i.carrier, ic, rot))?;
        // A linear actuator without a drive is a prismatic joint; the grease adjuster
        // locks it (`lock_adjuster`). The tensioner pushes the carrier rearward (-X) with
        // `preload + k s + c s_dot` at the forward travel `s`: on the carrier along the
        // slide's +X, `-preload - k s - c s_dot`.
        let t = &i.tensioner;
        let tensioner_slide = sys.add_joint(
            JointBuilder::at_axis(
                JointKind::LinearActuator {
                    drive: Drive::Effort(0.0),
                    max_force: f64::INFINITY,
                },
                chassis,
                carrier,
                ic,
                x_axis,
            )
            .axis_spring(AxisSpring {
                stiffness: t.stiffness,
                damping: t.damping,
                preload: -t.preload,
            })
            .name(label("tensioner_slide")),
        )?;
        let carrier_x0 = local_x(sys, chassis, ic)?;
        let idler = sys.add_body(dynamic("idler", &i.mass, ic, rot).collider(
            cylinder(i.radius, i.width),
            Isometry3::identity(),
            mat_wheel,
        ))?;
        revolute(sys, "idler_revolute", carrier, idler, ic)?;

        // Road wheels on trailing arms.
        let r = &data.road_wheels;
        let mut road_wheels = Vec::with_capacity(r.x.len());
        for (k, &x) in r.x.iter().enumerate() {
            let c = w([x, r.z]);
            let pivot = w([x + r.arm_pivot[0], r.z + r.arm_pivot[1]]);
            let arm = sys.add_body(dynamic(
                &format!("arm[{k}]"),
                &r.arm,
                0.5 * (c + pivot),
                rot,
            ))?;
            let damping = r.torsion_bar.damping
                + if r.shock_wheels.contains(&k) {
                    r.shock_damping
                } else {
                    0.0
                };
            // A rotational motor without a drive (angle limits: the bump stops, where given);
            // the torsion bar `T = T_0 - k theta - c omega` on the arm about Y.
            let arm_joint = sys.add_joint(
                JointBuilder::at_axis(
                    JointKind::RotationalMotor {
                        drive: Drive::Effort(0.0),
                        max_torque: f64::INFINITY,
                        limits: r.arm_travel.map(|[lo, hi]| (lo, hi)),
                    },
                    chassis,
                    arm,
                    pivot,
                    y_axis,
                )
                .axis_spring(AxisSpring {
                    stiffness: r.torsion_bar.stiffness,
                    damping,
                    preload: r.torsion_bar.preload,
                })
                .name(label(&format!("arm_revolute[{k}]"))),
            )?;
            let wheel = sys.add_body(
                dynamic(&format!("road_wheel[{k}]"), &r.wheel, c, rot).collider(
                    cylinder(r.radius, r.width),
                    Isometry3::identity(),
                    mat_wheel,
                ),
            )?;
            revolute(sys, &format!("road_wheel_revolute[{k}]"), arm, wheel, c)?;
            road_wheels.push(RoadWheel {
                wheel,
                arm,
                arm_joint,
            });
        }

        // Support rollers.
        let mut rollers = Vec::with_capacity(data.rollers.len());
        for (k, ro) in data.rollers.iter().enumerate() {
            let c = w(ro.location);
            let b = sys.add_body(dynamic(&format!("roller[{k}]"), &ro.mass, c, rot).collider(
                cylinder(ro.radius, ro.width),
                Isometry3::identity(),
                mat_wheel,
            ))?;
            revolute(sys, &format!("roller_revolute[{k}]"), chassis, b, c)?;
            rollers.push(b);
        }

        // Shoes and pins.
        let sh = &data.shoe;
        let n = lay.pins.len();
        let plate = Shape::Box {
            half_extents: Vector3::new(0.5 * sh.pitch, 0.5 * sh.width, 0.5 * sh.thickness),
        };
        let pin_end = cylinder(sh.pin_radius, s.gear_width + 0.02);
        let mut shoes = Vec::with_capacity(n);
        for k in 0..n {
            let (a, b) = (w(lay.pins[k]), w(lay.pins[(k + 1) % n]));
            let xl = (b - a).normalize();
            let zl = xl.cross(&y_axis);
            let q = UnitQuaternion::from_basis_unchecked(&[xl, y_axis, zl]);
            let mut bb = dynamic(&format!("shoe[{k}]"), &sh.mass, 0.5 * (a + b), q).collider(
                plate.clone(),
                Isometry3::identity(),
                mat_shoe,
            );
            for ring in [-1.0, 1.0] {
                bb = bb.collider(
                    pin_end.clone(),
                    Isometry3::translation(0.5 * sh.pitch, ring * s.gear_offset, 0.0),
                    mat_shoe,
                );
            }
            shoes.push(sys.add_body(bb)?);
        }
        // Pins 1..n: revolute joints. Pin 0 closes the loop: a revolute there would repeat
        // three rows (the loop's out-of-plane motion is already fixed by the others), which
        // makes the Schur solver's joint block singular and slow; two distance rows from the
        // pin on the last shoe to two points of the first (half a pitch along and across
        // it) fix the pin in the track plane only, so the rows stay independent.
        let mut pins = Vec::with_capacity(n);
        let p0 = w(lay.pins[0]);
        let q0 = sys.body(shoes[0])?.rotation();
        let mut closure = [None, None];
        for (i, dir) in [Vector3::x(), Vector3::z()].into_iter().enumerate() {
            let anchor = p0 + q0 * dir * (0.5 * sh.pitch);
            closure[i] = Some(
                sys.add_joint(
                    JointBuilder::distance_between(shoes[n - 1], shoes[0], p0, anchor)
                        .name(label(&format!("pin[0].closure[{i}]"))),
                )?,
            );
        }
        let closure = [closure[0].expect("set"), closure[1].expect("set")];
        pins.push(closure[0]);
        for k in 1..n {
            pins.push(revolute(
                sys,
                &format!("pin[{k}]"),
                shoes[k - 1],
                shoes[k],
                w(lay.pins[k]),
            )?);
        }
        Ok(Self {
            side,
            sprocket,
            sprocket_joint,
            idler,
            carrier,
            tensioner_slide,
            chassis,
            carrier_x0,
            road_wheels,
            rollers,
            shoes,
            pins,
            closure,
            layout: lay,
        })
    }

    /// Set the sprocket's drive: `Drive::Effort(t)` a torque (N m, about +Y: forward
    /// driving), `Drive::Speed(0.0)` held (a locked brake), `Drive::Speed(w)` a set speed.
    pub fn set_sprocket_drive(&self, sys: &mut System, drive: Drive) -> Result<()> {
        sys.joint_mut(self.sprocket_joint)?.set_drive(drive)?;
        Ok(())
    }

    /// The tensioner spring's force at the last step, N (positive pushes the idler
    /// rearward): `preload + k s + c s_dot` at the step's end. With the adjuster locked the
    /// lock carries the rest: see [`TrackAssembly::adjuster_force`].
    pub fn tensioner_force(&self, sys: &System) -> f64 {
        sys.joint(self.tensioner_slide)
            .map_or(f64::NAN, |j| -j.axis_spring_effort())
    }

    /// The idler carrier's travel from its assembled place along the chassis X axis, m
    /// (positive forward: the tensioner yielding to the chain).
    pub fn adjuster_travel(&self, sys: &System) -> Result<f64> {
        let x = sys.body(self.carrier)?.position();
        Ok(local_x(sys, self.chassis, x)? - self.carrier_x0)
    }

    /// Lock the adjuster (a grease cylinder holds its length,
    /// [`super::AdjusterKind::Grease`]): from now on the carrier's slide keeps its current
    /// travel, rigidly (a position row without a force limit). The spring-damper stays in
    /// parallel (at the locked travel its force is constant); the lock takes any change of
    /// the chain's pull.
    pub fn lock_adjuster(&self, sys: &mut System) -> Result<()> {
        let s = self.adjuster_travel(sys)?;
        sys.joint_mut(self.tensioner_slide)?
            .set_drive(Drive::Position(s))?;
        Ok(())
    }

    /// Road-wheel arm `k`'s rotation about the chassis Y axis from its assembled position,
    /// rad (positive: jounce, the wheel up towards the hull; the sign of
    /// [`super::RoadWheelData::arm_travel`]).
    pub fn arm_angle(&self, sys: &System, k: usize) -> Result<f64> {
        let arm = self.road_wheels.get(k).ok_or_else(|| {
            VehicleError::invalid("road_wheel", k, "no road wheel with this index")
        })?;
        let q = sys.body(self.chassis)?.rotation().inverse() * sys.body(arm.arm)?.rotation();
        let x = q * Vector3::x();
        Ok((-x.z).atan2(x.x))
    }

    /// The adjuster's whole push on the idler carrier at the last step, N (positive
    /// rearward, tensioning the chain): the spring-damper's force plus the lock's reaction
    /// along the slide (zero while unlocked). Both are rows of the slide, so this is its
    /// reaction along the slide.
    pub fn adjuster_force(&self, sys: &System) -> Result<f64> {
        let joint = sys.joint(self.tensioner_slide)?;
        let fwd = sys.body(self.chassis)?.rotation() * Vector3::x();
        Ok(-joint.reaction_force().dot(&fwd))
    }

    /// The magnitude of each pin joint's reaction force at the last step, N: the chain's
    /// tension at each pin (plus the pin's share of the shoes' weight and contact loads).
    /// Pin 0's is one of its two closure rows only.
    pub fn pin_forces(&self, sys: &System) -> Result<Vec<f64>> {
        self.pins
            .iter()
            .map(|&p| Ok(sys.joint(p)?.reaction_force().norm()))
            .collect()
    }

    /// Every body of the running gear except the shoes (sprocket, idler and carrier, road
    /// wheels and arms, rollers).
    pub fn running_gear(&self) -> Vec<BodyHandle> {
        let mut v = vec![self.sprocket, self.idler, self.carrier];
        for r in &self.road_wheels {
            v.push(r.wheel);
            v.push(r.arm);
        }
        v.extend(&self.rollers);
        v
    }
}

/// X of the world point `p` in `chassis`'s reference orientation about its centre of mass
/// (differences of it are travel along the chassis X axis), m.
fn local_x(sys: &System, chassis: BodyHandle, p: Vector3<f64>) -> Result<f64> {
    let c = sys.body(chassis)?;
    Ok((c.rotation().inverse() * (p - c.position())).x)
}

/// Distance from `p` to the segment `a b` in the plane, m.
pub(crate) fn segment_distance(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let (dx, dz) = (b[0] - a[0], b[1] - a[1]);
    let l2 = dx * dx + dz * dz;
    let t = if l2 > 0.0 {
        (((p[0] - a[0]) * dx + (p[1] - a[1]) * dz) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p[0] - a[0] - t * dx).hypot(p[1] - a[1] - t * dz)
}
