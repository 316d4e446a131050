//! The vertical-obstacle test: a rigid step (a fixed box on flat ground) ahead of a
//! tracked vehicle.
//!
//! [`TrackedStepScene`] is [`TrackedFlatScene`] (flat rigid ground at `z = 0`, the vehicle's
//! chassis reference at the world origin, facing +X, its lowest shoe just above the ground)
//! with a step whose vertical face is `gap` m ahead of the vehicle's foremost point
//! ([`front_x`]: sprocket teeth, the chain around the sprocket, or the hull) and whose top
//! is the plane `z = height`. The step's material is the data's `obstacle` material
//! ([`TrackedVehicleData::obstacle`]); each contact takes the lower friction of the pair.
//!
//! Example (the M113A1 in front of a 0.4 m step):
//!
//! ```no_run
//! use chrono_vehicle::m113::m113_data;
//! use chrono_vehicle::obstacle::{StepParams, TrackedStepScene};
//!
//! let step = StepParams { height: 0.4, gap: 0.5, length: 8.0, width: 5.0 };
//! let solver = Box::new(chrono_ccp::Schur::new(Default::default()));
//! let scene = TrackedStepScene::new(m113_data()?, 0.8, step, solver)?;
//! println!("face at x = {} m", scene.face_x);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use serde::{Deserialize, Serialize};

use chrono_ccp::CcpSolver;
use chrono_core::math::{Isometry3, Vector3};
use chrono_core::{BodyHandle, RigidBodyBuilder, Shape};

use crate::error::{Result, VehicleError, check_positive};
use crate::hull::lateral_reach;
use crate::tracked::{TrackedFlatScene, TrackedVehicleData};

/// The step (SI units; see the [module docs](self)).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StepParams {
    /// Height of the step's top above the ground, m (> 0).
    pub height: f64,
    /// Distance from the vehicle's foremost point to the face, m (> 0).
    pub gap: f64,
    /// Length of the step's top along X, m (> 0).
    pub length: f64,
    /// Width of the step across the vehicle, m: more than the vehicle's width over the
    /// running gear, so that both tracks meet it.
    pub width: f64,
}

impl StepParams {
    /// Check the fields for `data`'s vehicle (errors name `step.<field>`).
    pub fn validate(&self, data: &TrackedVehicleData) -> Result<()> {
        check_positive("step.height", self.height)?;
        check_positive("step.gap", self.gap)?;
        check_positive("step.length", self.length)?;
        check_positive("step.width", self.width)?;
        let span = 2.0 * (data.track_y + lateral_reach(&data.track));
        if self.width <= span {
            return Err(VehicleError::invalid(
                "step.width",
                self.width,
                format!("must exceed the vehicle's width over its running gear, {span:.3} m"),
            ));
        }
        Ok(())
    }
}

/// The foremost X of the vehicle in its chassis reference frame at assembly, m: the
/// sprocket's tooth tips, the chain's outer face around the sprocket (pitch radius plus
/// half a shoe thickness) or the hull's outline, whichever reaches furthest.
pub fn front_x(data: &TrackedVehicleData) -> f64 {
    let s = &data.track.sprocket;
    let sprocket = s.location[0]
        + s.tip_radius
            .max(s.pitch_radius + 0.5 * data.track.shoe.thickness);
    data.hull
        .as_ref()
        .map_or(sprocket, |h| sprocket.max(h.front_x()))
}

/// A tracked vehicle on flat ground in front of a step (see the [module docs](self)).
pub struct TrackedStepScene {
    /// The flat scene (system, vehicle, data, ground) with the step added.
    pub flat: TrackedFlatScene,
    /// The step's fixed body.
    pub step: BodyHandle,
    /// The step.
    pub params: StepParams,
    /// World X of the step's face, m.
    pub face_x: f64,
}

impl TrackedStepScene {
    /// Build the scene: ground friction `mu`, the step `step`, the CCP `solver`. Errors
    /// name the field: `step.<field>`, `obstacle` when the data has no obstacle material,
    /// or the vehicle data's.
    pub fn new(
        data: TrackedVehicleData,
        mu: f64,
        step: StepParams,
        solver: Box<dyn CcpSolver>,
    ) -> Result<Self> {
        data.validate()?;
        step.validate(&data)?;
        let material = data.obstacle.ok_or_else(|| {
            VehicleError::invalid(
                "obstacle",
                "none",
                "the vehicle data needs an obstacle material for the step",
            )
        })?;
        let face_x = front_x(&data) + step.gap;
        let mut flat = TrackedFlatScene::new(data, mu, solver)?;
        let step_body = flat.sys.add_body(
            RigidBodyBuilder::fixed()
                .name("step")
                .position(Vector3::new(
                    face_x + 0.5 * step.length,
                    0.0,
                    0.5 * step.height,
                ))
                .collider(
                    Shape::Box {
                        half_extents: Vector3::new(
                            0.5 * step.length,
                            0.5 * step.width,
                            0.5 * step.height,
                        ),
                    },
                    Isometry3::identity(),
                    material,
                ),
        )?;
        Ok(Self {
            flat,
            step: step_body,
            params: step,
            face_x,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::m113::m113_data;

    fn solver() -> Box<dyn CcpSolver> {
        Box::new(chrono_ccp::Schur::new(Default::default()))
    }

    fn step() -> StepParams {
        StepParams {
            height: 0.488,
            gap: 0.5,
            length: 8.0,
            width: 5.0,
        }
    }

    /// The scene builds with the step's face `gap` ahead of the vehicle and nothing
    /// touching the step or the hull; one step later the vehicle rests on the ground
    /// (its chains closed) and still touches neither.
    #[test]
    fn the_m113_step_scene_builds_clear_of_the_step() {
        let mut s = TrackedStepScene::new(m113_data().unwrap(), 0.8, step(), solver()).unwrap();
        let d = &s.flat.data;
        assert!((s.face_x - (front_x(d) + 0.5)).abs() < 1e-12);
        // The hull is the foremost part only if its outline reaches past the chain.
        assert!(front_x(d) >= d.track.sprocket.tip_radius);
        let chassis = s.flat.vehicle.chassis;
        assert!(!s.flat.sys.body(chassis).unwrap().colliders().is_empty());
        s.flat.sys.step(2e-3).unwrap();
        let set = s.flat.sys.body_set();
        let (ch, st) = (
            set.dense_index(chassis).unwrap(),
            set.dense_index(s.step).unwrap(),
        );
        for c in s.flat.sys.contacts() {
            let (a, b) = (c.point.owner_a as usize, c.point.owner_b as usize);
            assert!(a != st && b != st, "a contact with the step at the start");
            assert!(a != ch && b != ch, "a contact with the hull at the start");
        }
        assert!(s.flat.sys.max_joint_violation() < 1e-3);
    }

    #[test]
    fn bad_step_input_is_an_error_naming_the_field() {
        let build = |st: StepParams, d: TrackedVehicleData| {
            TrackedStepScene::new(d, 0.8, st, solver())
                .err()
                .map(|e| e.to_string())
                .unwrap_or_default()
        };
        let d = m113_data().unwrap();
        for (name, st) in [
            (
                "step.height",
                StepParams {
                    height: -0.1,
                    ..step()
                },
            ),
            (
                "step.height",
                StepParams {
                    height: f64::NAN,
                    ..step()
                },
            ),
            (
                "step.gap",
                StepParams {
                    gap: f64::NAN,
                    ..step()
                },
            ),
            ("step.gap", StepParams { gap: 0.0, ..step() }),
            (
                "step.length",
                StepParams {
                    length: -1.0,
                    ..step()
                },
            ),
            (
                "step.width",
                StepParams {
                    width: 2.0,
                    ..step()
                },
            ),
        ] {
            let e = build(st, d.clone());
            assert!(e.contains(name), "{name}: {e}");
        }
        let mut no_mat = d.clone();
        no_mat.obstacle = None;
        assert!(build(step(), no_mat).contains("obstacle"));
        let mut bad_mat = d;
        bad_mat.obstacle.as_mut().unwrap().friction = -1.0;
        assert!(build(step(), bad_mat).contains("obstacle"));
    }
}
