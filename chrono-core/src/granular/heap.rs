//! The angle of repose of a heap left on a plate after discharge over both edges, in a slot.
//!
//! Setup of Y. C. Zhou, B. H. Xu, A. B. Yu and P. Zulli, "An experimental and numerical
//! study of the angle of repose of coarse spheres", Powder Technol. 125 (2002) 45–54:
//! mono-sized spheres settle on a plate between two vertical walls `thickness` apart, held
//! at the plate's ends by two gates; the gates open, the grains flow off both edges, and
//! the heap that stays on the plate has the angle of repose. Their DEM heaps for a slot of
//! `4 d` fit (their Eq. 3, standard deviation 2 degrees)
//!
//! `theta = 102 mu_pp^0.27 mu_pw^0.22 mr_pp^0.06 mr_pw^0.12 d^-0.2` (degrees),
//!
//! with the rolling friction coefficients `mr` as lengths and `d` in mm.
//!
//! A [`HeapSlot`] adds the slot, the plate and the gates to a [`System`] the caller made
//! (contact method, solver, settings) and pours the bed ([`HeapSlot::build`]); the
//! [`HeapScene`] it returns settles the bed with the gates closed, opens them, lets the
//! grains flow off and reads the [`Heap`] ([`HeapScene::run`]). A grain that has fallen
//! `2 d` below the plate is parked at rest on a floor `30 d` down, far from the plate, so
//! discharged grains cost no contacts.
//!
//! The heap's surface is the highest grain centre in each column of width `~d` over the
//! plate ([`heap_profile`]); a least-squares line over both flanks, `|x|` between 15 % and
//! 85 % of the half-width (neither the crest nor the toe), gives its angle
//! ([`flank_angles`]).

use nalgebra::{Isometry3, UnitQuaternion, Vector3};

use super::bed::{Bed, GrainBed, Kick, Settle};
use super::fill::Region;
use super::probe::{flank_angles, heap_profile};
use super::step_size;
use crate::body::{BodyHandle, RigidBodyBuilder};
use crate::error::{ChronoError, Result, check_non_negative, check_positive};
use crate::material::{ContactFriction, ContactMaterial};
use crate::shape::Shape;
use crate::system::System;

/// The salt of the bed's kick (its random horizontal velocities).
const KICK_SALT: u64 = 0x5851_f42d_4c95_7f2d;

/// A heap of mono-sized grains (diameters uniform in `[0.95 d, d]`) settled between two
/// gates on a plate in a slot (Z up, the plate along x centred on `x = 0`, the slot's walls
/// at `y = 0` and `y = thickness d`, the plate's top at `z = 0`), then discharged over both
/// edges. Lengths of the scene are in grain diameters `d`, as Zhou et al. give them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HeapSlot {
    /// Largest grain diameter `d`, m.
    pub grain_diameter: f64,
    /// Plate length, in grain diameters (Zhou et al.: 30).
    pub plate_width: f64,
    /// Slot thickness (gap between the walls), in grain diameters (Zhou et al.: 4).
    pub thickness: f64,
    /// Height of the settled bed before discharge, in grain diameters (it must exceed the
    /// heap's, `plate_width / 2 tan(theta)`, or the heap keeps a flat top).
    pub bed_height: f64,
    /// Grain density, kg/m^3.
    pub density: f64,
    /// Contact material of the grains, also given to the walls, the plate and the gates.
    pub material: ContactMaterial,
    /// Friction of every grain contact with the walls, the plate and the gates (Zhou et
    /// al.'s particle–wall pair `mu_pw`, `mr_pw`): a per-body override
    /// ([`System::set_contact_friction`]), since materials combine by the minimum.
    pub wall_friction: ContactFriction,
    /// Glue a layer of fixed spheres of diameter `d` (touching, square lattice, the grains'
    /// material) on the plate: a rough base instead of the smooth plate.
    pub rough_base: bool,
    /// Seed of the packing (radii, jitter, kick).
    pub seed: u64,
    /// Time step, s (0: [`step_size`]'s, 1 ms for NSC, the SMC stability limit for SMC).
    pub h: f64,
    /// Settling time with the gates closed, s.
    pub t_settle: f64,
    /// Discharge time after the gates open, s.
    pub t_discharge: f64,
}

/// The bodies of a heap slot.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct HeapSlotBodies {
    /// The wall at `y = 0` (fixed half-space, "front wall").
    pub front: BodyHandle,
    /// The wall at `y = thickness d` (fixed half-space, "back wall").
    pub back: BodyHandle,
    /// The floor `30 d` below the plate where discharged grains are parked ("park floor").
    pub park_floor: BodyHandle,
    /// The plate (fixed box, its top at `z = 0`).
    pub plate: BodyHandle,
    /// The layer of fixed spheres on the plate, with [`HeapSlot::rough_base`].
    pub rough_base: Option<BodyHandle>,
    /// The gates at the plate's ends, `[left (x < 0), right]` (fixed half-spaces).
    pub gates: [BodyHandle; 2],
}

/// The heap left on the plate.
#[derive(Debug, Clone, PartialEq)]
pub struct Heap {
    /// Angle of both flanks fitted together, degrees.
    pub angle: f64,
    /// Angles of the left (`x < 0`) and right flanks, degrees.
    pub flanks: [f64; 2],
    /// Highest grain centre above the plate, m.
    pub crest: f64,
    /// Grains of the bed.
    pub grains: usize,
    /// Grains left on the plate.
    pub on_plate: usize,
    /// Kinetic energy per grain on the plate, in units of `m g d` (`m` their mean mass).
    pub ke: f64,
    /// The surface: column centre `x` (m) and its highest grain centre `z` (m), NaN where
    /// the column is empty.
    pub profile: Vec<(f64, f64)>,
}

/// A grain left on the plate, as [`Heap::measure`] reads it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HeapGrain {
    /// Position of the centre along the plate, m.
    pub x: f64,
    /// Height of the centre above the plate's top, m.
    pub z: f64,
    /// Mass, kg.
    pub mass: f64,
    /// Kinetic energy, J.
    pub kinetic_energy: f64,
}

impl Heap {
    /// The heap of the grains `on_plate` (of `grains` in the bed) on a plate `half_width`
    /// (m) either side of `x = 0`, its surface read over `columns` columns; the kinetic
    /// energy per grain in units of `m g d` (grain diameter `d`, m; gravity `g`, m/s^2).
    /// Errors name `heap.on_plate` when no grain is left, `heap.plate_width` when a flank
    /// has too few columns to fit a slope.
    pub fn measure(
        on_plate: &[HeapGrain],
        grains: usize,
        half_width: f64,
        columns: usize,
        d: f64,
        g: f64,
    ) -> Result<Heap> {
        let n = on_plate.len();
        if n == 0 {
            return Err(ChronoError::invalid(
                "heap.on_plate",
                0,
                "no grain is left on the plate",
            ));
        }
        let points: Vec<(f64, f64)> = on_plate.iter().map(|q| (q.x, q.z)).collect();
        let (mut ke, mut mass) = (0.0, 0.0);
        for q in on_plate {
            ke += q.kinetic_energy;
            mass += q.mass;
        }
        let mean_mass = mass / n as f64;
        let profile = heap_profile(
            &points,
            -half_width,
            2.0 * half_width / columns as f64,
            columns,
        );
        let (angle, flanks) = flank_angles(&profile, half_width).ok_or_else(|| {
            ChronoError::invalid(
                "heap.plate_width",
                columns,
                "too few surface columns on a flank to fit a slope (3 in the fitted band)",
            )
        })?;
        Ok(Heap {
            angle,
            flanks,
            crest: points.iter().map(|q| q.1).fold(f64::MIN, f64::max),
            grains,
            on_plate: n,
            ke: ke / n as f64 / (mean_mass * g * d),
            profile,
        })
    }
}

/// A fixed body with one half-space collider through `at` with outward `normal`.
fn half_space(
    sys: &mut System,
    name: &str,
    normal: Vector3<f64>,
    at: Vector3<f64>,
    mat: ContactMaterial,
) -> Result<BodyHandle> {
    sys.add_body(RigidBodyBuilder::fixed().name(name).collider(
        Shape::HalfSpace { normal },
        Isometry3::translation(at.x, at.y, at.z),
        mat,
    ))
}

impl HeapSlot {
    /// Zhou et al.'s slot for grains of diameter `d` (m) and `material`: a 30 d plate, a
    /// 4 d slot, a 14 d bed of density 2500 kg/m^3, the walls with the grains' own friction,
    /// a smooth plate, seed 1, the default step, 0.6 s of settling and 8 s of discharge.
    pub fn new(grain_diameter: f64, material: ContactMaterial) -> Self {
        Self {
            grain_diameter,
            plate_width: 30.0,
            thickness: 4.0,
            bed_height: 14.0,
            density: 2500.0,
            material,
            wall_friction: ContactFriction {
                friction: material.friction,
                rolling_friction: material.rolling_friction,
                spinning_friction: 0.0,
            },
            rough_base: false,
            seed: 1,
            h: 0.0,
            t_settle: 0.6,
            t_discharge: 8.0,
        }
    }

    /// Half the plate's length, m.
    pub fn half_width(&self) -> f64 {
        0.5 * self.plate_width * self.grain_diameter
    }

    /// Errors naming the field (`heap.*`) unless the scene can be built.
    pub fn validate(&self) -> Result<()> {
        check_positive("heap.grain_diameter", self.grain_diameter)?;
        check_positive("heap.density", self.density)?;
        check_positive("heap.bed_height", self.bed_height)?;
        check_non_negative("heap.t_settle", self.t_settle)?;
        check_positive("heap.t_discharge", self.t_discharge)?;
        check_non_negative("heap.h", self.h)?;
        if !(self.plate_width.is_finite() && self.plate_width >= 1.0) {
            return Err(ChronoError::invalid(
                "heap.plate_width",
                self.plate_width,
                "must be at least 1 grain diameter",
            ));
        }
        if !(self.thickness.is_finite() && self.thickness > 1.0) {
            return Err(ChronoError::invalid(
                "heap.thickness",
                self.thickness,
                "must exceed 1 grain diameter",
            ));
        }
        self.material.validate()
    }

    /// Adds the slot's walls, the park floor, the plate, the rough base if any and the
    /// closed gates to `sys` (in that order), with [`HeapSlot::wall_friction`] on the
    /// walls, the plate and the gates.
    pub fn add(&self, sys: &mut System) -> Result<HeapSlotBodies> {
        self.validate()?;
        let d = self.grain_diameter;
        let r = 0.5 * d;
        let (half, w) = (self.half_width(), self.thickness * d);
        let mat = self.material;
        let front = half_space(sys, "front wall", Vector3::y(), Vector3::zeros(), mat)?;
        let back = half_space(
            sys,
            "back wall",
            -Vector3::y(),
            Vector3::new(0.0, w, 0.0),
            mat,
        )?;
        let park_floor = half_space(
            sys,
            "park floor",
            Vector3::z(),
            Vector3::new(0.0, 0.0, self.park_height()),
            mat,
        )?;
        let plate = sys.add_body(RigidBodyBuilder::fixed().name("plate").collider(
            Shape::Box {
                half_extents: Vector3::new(half, 0.5 * w, r),
            },
            Isometry3::translation(0.0, 0.5 * w, -r),
            mat,
        ))?;
        let rough_base = if self.rough_base {
            // Touching spheres of diameter d on the plate, one fixed body.
            let (nx, ny) = ((2.0 * half / d).floor() as usize, (w / d).floor() as usize);
            let mut base = RigidBodyBuilder::fixed().name("rough base");
            for i in 0..nx {
                for j in 0..ny {
                    let x = -half + r + i as f64 * d;
                    let y = r + j as f64 * d + 0.5 * (w - ny as f64 * d);
                    base = base.collider(
                        Shape::Sphere { radius: r },
                        Isometry3::translation(x, y, r),
                        mat,
                    );
                }
            }
            Some(sys.add_body(base)?)
        } else {
            None
        };
        let gates = [
            half_space(
                sys,
                "left gate",
                Vector3::x(),
                Vector3::new(-half, 0.0, 0.0),
                mat,
            )?,
            half_space(
                sys,
                "right gate",
                -Vector3::x(),
                Vector3::new(half, 0.0, 0.0),
                mat,
            )?,
        ];
        for b in [front, back, plate, gates[0], gates[1]] {
            sys.set_contact_friction(b, Some(self.wall_friction))?;
        }
        Ok(HeapSlotBodies {
            front,
            back,
            park_floor,
            plate,
            rough_base,
            gates,
        })
    }

    /// Height of the park floor, m (`30 d` below the plate).
    fn park_height(&self) -> f64 {
        -30.0 * self.grain_diameter
    }

    /// The bed behind the gates: the grain count of a bed `bed_height` high at a solid
    /// fraction of 0.58, on a loose jittered lattice (sites 1.25 d apart, which settles to
    /// ~0.6) in a region 4 times that high over the plate (or the rough base), kicked at
    /// 0.1 m/s to break the lattice's columns; no settling (the scene settles it).
    pub fn grain_bed(&self) -> GrainBed {
        let d = self.grain_diameter;
        let r = 0.5 * d;
        let (half, w) = (self.half_width(), self.thickness * d);
        let base_top = if self.rough_base { d } else { 0.0 };
        let v_grain = std::f64::consts::PI / 6.0 * (0.975 * d).powi(3);
        let count = (0.58 * 2.0 * half * w * self.bed_height * d / v_grain).round() as usize;
        GrainBed {
            count: Some(count),
            seed: self.seed,
            kick: Some(Kick {
                speed: 0.1,
                salt: KICK_SALT,
            }),
            ..GrainBed::new(
                Region::Box {
                    lower: Vector3::new(-half, 0.0, base_top),
                    upper: Vector3::new(half, w, base_top + 4.0 * self.bed_height * d),
                },
                0.95 * r,
                r,
                self.density,
                self.material,
            )
        }
    }

    /// Adds the slot ([`HeapSlot::add`]) and pours the bed ([`HeapSlot::grain_bed`]) into
    /// `sys`, a system the caller made (contact method, solver, settings); the step is
    /// fixed once the grains are in (SMC's stability limit depends on them).
    pub fn build(&self, sys: &mut System) -> Result<HeapScene> {
        let bodies = self.add(sys)?;
        let spec = self.grain_bed();
        let bed = spec.pour(sys)?;
        let h = step_size(self.h, sys.settings().contact_method, sys);
        let d = self.grain_diameter;
        let w = self.thickness * d;
        let parking = Parking {
            parked: vec![false; bed.len()],
            count: 0,
            rows: ((w / (1.5 * d)).floor() as usize).max(1),
            d,
            half: self.half_width(),
            w,
            z: self.park_height(),
        };
        Ok(HeapScene {
            slot: *self,
            bodies,
            spec,
            bed,
            h,
            parking,
        })
    }
}

/// The grains parked on the far floor.
#[derive(Debug, Clone)]
struct Parking {
    parked: Vec<bool>,
    count: usize,
    rows: usize,
    d: f64,
    half: f64,
    w: f64,
    z: f64,
}

impl Parking {
    /// Parks the grains of `handles` that fell `2 d` below the plate: at rest on the
    /// floor, 1.5 d apart in rows beyond the plate's end, touching nothing but the floor.
    fn park(&mut self, sys: &mut System, handles: &[BodyHandle]) -> Result<()> {
        let (d, half, w) = (self.d, self.half, self.w);
        let r = 0.5 * d;
        for (k, &b) in handles.iter().enumerate() {
            if self.parked[k] || sys.body(b)?.position().z > -2.0 * d {
                continue;
            }
            let (col, row) = (self.count / self.rows, self.count % self.rows);
            let at = Vector3::new(
                half + 10.0 * d + 1.5 * d * col as f64,
                (row as f64 + 0.5) * w / self.rows as f64,
                self.z + 1.01 * r,
            );
            let body = sys.body_mut(b)?;
            body.set_pose(at, UnitQuaternion::identity())?;
            body.set_linear_velocity(Vector3::zeros())?;
            body.set_angular_velocity(Vector3::zeros())?;
            self.parked[k] = true;
            self.count += 1;
        }
        Ok(())
    }
}

/// A built heap slot: its bodies, the poured bed and the step.
#[derive(Debug, Clone)]
pub struct HeapScene {
    slot: HeapSlot,
    bodies: HeapSlotBodies,
    spec: GrainBed,
    bed: Bed,
    h: f64,
    parking: Parking,
}

impl HeapScene {
    /// The time step, s.
    pub fn h(&self) -> f64 {
        self.h
    }

    /// The slot's bodies.
    pub fn bodies(&self) -> &HeapSlotBodies {
        &self.bodies
    }

    /// The poured bed.
    pub fn bed(&self) -> &Bed {
        &self.bed
    }

    /// Steps with the gates closed, `round(t_settle / h)`.
    pub fn settle_steps(&self) -> u64 {
        (self.slot.t_settle / self.h).round() as u64
    }

    /// Steps of the whole run: settling, then `max(1, round(t_discharge / h))`.
    pub fn total_steps(&self) -> u64 {
        self.settle_steps() + (self.slot.t_discharge / self.h).round().max(1.0) as u64
    }

    /// Grains parked so far (discharged off the plate).
    pub fn parked(&self) -> usize {
        self.parking.count
    }

    /// Settles the bed with the gates closed, opens them (moves them 100 m outwards, out
    /// of the scene) and lets the grains flow off the plate for `t_discharge`, parking the
    /// discharged ones; returns the heap left ([`HeapScene::heap`]). `on_step(sys, step)`
    /// is called after each step (step counted from 1 to [`HeapScene::total_steps`]; VTK
    /// frames, progress), before the grains that left are parked.
    pub fn run<E: From<ChronoError>>(
        &mut self,
        sys: &mut System,
        mut on_step: impl FnMut(&mut System, u64) -> std::result::Result<(), E>,
    ) -> std::result::Result<Heap, E> {
        let (h, n_settle, n) = (self.h, self.settle_steps(), self.total_steps());
        let (handles, parking) = (&self.bed.handles, &mut self.parking);
        GrainBed {
            settle: Settle::Steps(n_settle),
            ..self.spec
        }
        .settle(sys, &self.bed, h, |sys, i| {
            on_step(sys, i)?;
            parking.park(sys, handles)?;
            Ok::<(), E>(())
        })?;
        for (g, s) in self.bodies.gates.iter().zip([-1.0, 1.0]) {
            sys.body_mut(*g)?.set_pose(
                Vector3::new(100.0 * s, 0.0, 0.0),
                UnitQuaternion::identity(),
            )?;
        }
        for i in n_settle + 1..=n {
            sys.step(h)?;
            on_step(sys, i)?;
            parking.park(sys, handles)?;
        }
        Ok(self.heap(sys)?)
    }

    /// The heap of the grains not parked, its surface over columns of width
    /// `plate_width / round(plate_width)` grain diameters ([`Heap::measure`]).
    pub fn heap(&self, sys: &System) -> Result<Heap> {
        let g = sys.settings().gravity.norm();
        let mut on_plate = Vec::new();
        for (k, &b) in self.bed.handles.iter().enumerate() {
            if self.parking.parked[k] {
                continue;
            }
            let body = sys.body(b)?;
            let x = body.position();
            on_plate.push(HeapGrain {
                x: x.x,
                z: x.z,
                mass: body.mass(),
                kinetic_energy: body.kinetic_energy(),
            });
        }
        Heap::measure(
            &on_plate,
            self.bed.len(),
            self.slot.half_width(),
            self.slot.plate_width.round() as usize,
            self.slot.grain_diameter,
            g,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn heap_of_a_synthetic_cone() {
        // Grains on a 30-degree heap of half-width 0.15 m, one per 2.5 mm, heavier on the
        // right: the fit recovers the angle, the crest and the energy in m g d.
        let (half, d, g) = (0.15, 0.01, crate::math::GRAVITY.norm());
        let slope = 30f64.to_radians().tan();
        let grains: Vec<HeapGrain> = (0..120)
            .map(|i| -half + (i as f64 + 0.5) * 0.0025)
            .map(|x| HeapGrain {
                x,
                z: (half - x.abs()) * slope,
                mass: if x > 0.0 { 3.0 } else { 1.0 },
                kinetic_energy: 1e-3,
            })
            .collect();
        let heap = Heap::measure(&grains, 200, half, 30, d, g).unwrap();
        assert!((heap.angle - 30.0).abs() < 0.5, "{}", heap.angle);
        assert!(heap.flanks.iter().all(|a| (a - 30.0).abs() < 0.5));
        assert!((heap.crest - half * slope).abs() < 0.01, "{}", heap.crest);
        assert_eq!(
            (heap.grains, heap.on_plate, heap.profile.len()),
            (200, 120, 30)
        );
        assert!(
            (heap.ke - 1e-3 / (2.0 * g * d)).abs() < 1e-12,
            "{}",
            heap.ke
        );
    }

    #[test]
    fn empty_plate_and_bad_fields_are_named() {
        let e = Heap::measure(&[], 10, 0.15, 30, 0.01, 1.0)
            .unwrap_err()
            .to_string();
        assert!(e.contains("heap.on_plate"), "{e}");
        let one = [HeapGrain {
            x: 0.0,
            z: 0.01,
            mass: 1.0,
            kinetic_energy: 0.0,
        }];
        let e = Heap::measure(&one, 1, 0.15, 30, 0.01, 1.0)
            .unwrap_err()
            .to_string();
        assert!(e.contains("heap.plate_width"), "{e}");
        let mat = ContactMaterial::smc(1e7, 0.3, 0.5, 0.4);
        let slot = HeapSlot {
            thickness: 0.5,
            ..HeapSlot::new(0.01, mat)
        };
        let e = slot.validate().unwrap_err().to_string();
        assert!(e.contains("heap.thickness") && e.contains("0.5"), "{e}");
        let slot = HeapSlot {
            grain_diameter: -1.0,
            ..HeapSlot::new(0.01, mat)
        };
        assert!(
            slot.validate()
                .unwrap_err()
                .to_string()
                .contains("heap.grain_diameter")
        );
        assert!(HeapSlot::new(0.01, mat).validate().is_ok());
    }
}
