//! The direct shear box: a square box split at the shear plane `z = 0` into a lower half
//! that is driven sideways and a fixed upper half, with a load plate on the sample; the
//! forces read on them and the reduction of the measured curve (peak and residual of the
//! force ratio, dilation rate).
//!
//! The bulk friction is the ratio of the shear force across the shear plane to the normal
//! force on it, `mu_b = S / N`, its angle `phi = atan(S / N)` (Mohr–Coulomb without
//! cohesion, `tau = sigma tan(phi)`). Taylor's energy balance (D. W. Taylor, *Fundamentals
//! of Soil Mechanics*, Wiley 1948, ch. 14; M. D. Bolton, "The strength and dilatancy of
//! sands", Géotechnique 36 (1986) 65–78) relates the ratio to the load plate's rise:
//! `S dx = mu_cv N dx + N dy`, so `S / N = mu_cv + dy/dx` ([`dilation_rate`]).
//!
//! The test itself (pour, consolidation, shear at constant speed, the read-out by bins) is
//! [`ShearTest`](super::shear_test::ShearTest).

use nalgebra::{Isometry3, UnitQuaternion, Vector3};

use super::probe::{grain_forces_on, line_fit};
use crate::body::{BodyHandle, RigidBodyBuilder};
use crate::error::{ChronoError, Result, check_positive};
use crate::joint::{JointBuilder, JointHandle, JointKind};
use crate::material::ContactMaterial;
use crate::shape::Shape;
use crate::system::System;

/// A direct shear box (Z up, shear along +x), the shear plane at `z = 0`.
///
/// The lower half (floor and four walls of box colliders, `half_height` deep) is
/// kinematic; the upper half (four walls from `gap` above the plane to `top`) is fixed; the
/// load plate (a box `length - plate_clearance` wide, `wall` thick) is free to slide
/// vertically in the upper half on a prismatic joint.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShearBox {
    /// Inner side of the square box, m.
    pub length: f64,
    /// Depth of the lower half below the shear plane, m.
    pub half_height: f64,
    /// Gap between the two halves, m (below a grain diameter: no grain passes).
    pub gap: f64,
    /// Thickness of the walls, the floor and the plate, m.
    pub wall: f64,
    /// Height of the upper half's walls' top, m.
    pub top: f64,
    /// The plate is this much narrower than the box, m.
    pub plate_clearance: f64,
    /// Mass of the load plate, kg.
    pub plate_mass: f64,
    /// Contact material of the box and the plate.
    pub material: ContactMaterial,
}

/// The bodies of a shear box.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ShearBoxBodies {
    /// The lower half (kinematic).
    pub lower: BodyHandle,
    /// The upper half (fixed).
    pub upper: BodyHandle,
    /// The load plate (dynamic).
    pub plate: BodyHandle,
    /// The plate's vertical slider on the upper half.
    pub slider: JointHandle,
}

impl ShearBoxBodies {
    /// The box's bodies (everything that is not a grain), for [`grain_forces_on`] and
    /// [`uniaxial_overlap_strain`](super::probe::uniaxial_overlap_strain).
    pub fn structure(&self) -> [BodyHandle; 3] {
        [self.lower, self.upper, self.plate]
    }
}

/// Four walls of thickness `t` around the square `[-l/2, l/2]^2`, between heights `z0` and
/// `z1`, as box colliders on `b`.
fn add_walls(
    mut b: RigidBodyBuilder,
    l: f64,
    t: f64,
    z0: f64,
    z1: f64,
    mat: ContactMaterial,
) -> RigidBodyBuilder {
    let (hz, zc) = (0.5 * (z1 - z0), 0.5 * (z0 + z1));
    let off = 0.5 * (l + t);
    for s in [-1.0, 1.0] {
        b = b
            .collider(
                Shape::Box {
                    half_extents: Vector3::new(0.5 * t, 0.5 * l + t, hz),
                },
                Isometry3::translation(s * off, 0.0, zc),
                mat,
            )
            .collider(
                Shape::Box {
                    half_extents: Vector3::new(0.5 * l, 0.5 * t, hz),
                },
                Isometry3::translation(0.0, s * off, zc),
                mat,
            );
    }
    b
}

impl ShearBox {
    /// Side of the load plate, m.
    pub fn plate_side(&self) -> f64 {
        self.length - self.plate_clearance
    }

    /// Adds the lower half, the upper half, the plate and its slider to `sys` (in that
    /// order). The plate is parked above the upper half's walls, its weight carried by an
    /// applied force, while grains are poured: [`ShearBox::load`] puts it on the sample.
    pub fn add(&self, sys: &mut System) -> Result<ShearBoxBodies> {
        check_positive("shear_box.length", self.length)?;
        check_positive("shear_box.half_height", self.half_height)?;
        check_positive("shear_box.wall", self.wall)?;
        check_positive("shear_box.plate_mass", self.plate_mass)?;
        if !(self.top.is_finite() && self.top > self.gap) {
            return Err(ChronoError::invalid(
                "shear_box.top",
                self.top,
                format!("must exceed shear_box.gap = {}", self.gap),
            ));
        }
        let (l, hl, t) = (self.length, self.half_height, self.wall);
        let g = sys.settings().gravity.norm();
        let floor = Shape::Box {
            half_extents: Vector3::new(0.5 * l + t, 0.5 * l + t, 0.5 * t),
        };
        let lower_b = RigidBodyBuilder::kinematic().name("lower half").collider(
            floor,
            Isometry3::translation(0.0, 0.0, -hl - 0.5 * t),
            self.material,
        );
        let lower = sys.add_body(add_walls(lower_b, l, t, -hl, 0.0, self.material))?;
        let upper_b = RigidBodyBuilder::fixed().name("upper half");
        let upper = sys.add_body(add_walls(upper_b, l, t, self.gap, self.top, self.material))?;
        let side = self.plate_side();
        if !(side.is_finite() && side > 0.0) {
            return Err(ChronoError::invalid(
                "shear_box.plate_clearance",
                self.plate_clearance,
                format!("must be below shear_box.length = {l}"),
            ));
        }
        let plate_shape = Shape::Box {
            half_extents: Vector3::new(0.5 * side, 0.5 * side, 0.5 * t),
        };
        let park = self.top + t;
        let plate = sys.add_body(
            RigidBodyBuilder::dynamic()
                .name("load plate")
                .mass_from_shape(&plate_shape, self.plate_mass / (side * side * t))?
                .position(Vector3::new(0.0, 0.0, park))
                .collider(plate_shape, Isometry3::identity(), self.material),
        )?;
        let slider = sys.add_joint(
            JointBuilder::at_axis(
                JointKind::Prismatic,
                upper,
                plate,
                Vector3::new(0.0, 0.0, park),
                Vector3::z(),
            )
            .name("plate slider"),
        )?;
        sys.body_mut(plate)?
            .set_applied_force(Vector3::new(0.0, 0.0, self.plate_mass * g))?;
        Ok(ShearBoxBodies {
            lower,
            upper,
            plate,
            slider,
        })
    }

    /// Puts the plate at rest `clearance` (m) above `sample_top` (m, the highest grain's
    /// top) and loads the sample with `load` (N) in all, the plate's weight included.
    pub fn load(
        &self,
        sys: &mut System,
        bodies: &ShearBoxBodies,
        sample_top: f64,
        clearance: f64,
        load: f64,
    ) -> Result<()> {
        let g = sys.settings().gravity.norm();
        let body = sys.body_mut(bodies.plate)?;
        body.set_pose(
            Vector3::new(0.0, 0.0, sample_top + 0.5 * self.wall + clearance),
            UnitQuaternion::identity(),
        )?;
        body.set_linear_velocity(Vector3::zeros())?;
        body.set_applied_force(Vector3::new(0.0, 0.0, -(load - self.plate_mass * g)))?;
        Ok(())
    }

    /// Starts the lower half moving along +x at `speed` (m/s).
    pub fn drive(&self, sys: &mut System, bodies: &ShearBoxBodies, speed: f64) -> Result<()> {
        sys.body_mut(bodies.lower)?
            .set_linear_velocity(Vector3::new(speed, 0.0, 0.0))
    }

    /// Volume (m^3) of the sample between the floor and the plate's underside.
    pub fn sample_volume(&self, sys: &System, bodies: &ShearBoxBodies) -> Result<f64> {
        let z_plate = sys.body(bodies.plate)?.position().z;
        Ok(self.length * self.length * (z_plate - 0.5 * self.wall + self.half_height))
    }

    /// The forces (N) the grains exert, in the last step of length `h` (s), on the upper
    /// half with the plate, and on the lower half.
    pub fn grain_forces(
        &self,
        sys: &System,
        bodies: &ShearBoxBodies,
        h: f64,
    ) -> (Vector3<f64>, Vector3<f64>) {
        let structure = bodies.structure();
        (
            grain_forces_on(sys, h, &[bodies.upper, bodies.plate], &structure),
            grain_forces_on(sys, h, &[bodies.lower], &structure),
        )
    }
}

/// Index of the middle bin of the peak: the 3-bin window of bins `(s, ratio)` (increasing
/// displacement) with the largest mean ratio among those centred at `s <= peak_window s_max`.
pub fn peak_bin(bins: &[(f64, f64)], peak_window: f64) -> Option<usize> {
    let s_max = bins.last().map(|b| b.0).unwrap_or(0.0);
    let mut best: Option<(usize, f64)> = None;
    for (i, w) in bins.windows(3).enumerate() {
        let mean = (w[0].1 + w[1].1 + w[2].1) / 3.0;
        if w[1].0 <= peak_window * s_max && best.is_none_or(|(_, m)| mean > m) {
            best = Some((i + 1, mean));
        }
    }
    best.map(|(i, _)| i)
}

/// Peak (largest 3-bin running mean over the bins with `s <= peak_window s_max`, see
/// [`peak_bin`]) and residual (mean over `s >= (1 - residual_window) s_max`) of a ratio
/// sampled in bins `(s, ratio)` of increasing displacement. Errors name `bins` (fewer than
/// 6) or the window that selects none.
pub fn peak_and_residual(
    bins: &[(f64, f64)],
    peak_window: f64,
    residual_window: f64,
) -> Result<(f64, f64)> {
    if bins.len() < 6 {
        return Err(ChronoError::invalid(
            "bins",
            bins.len(),
            "too few for a peak and a residual (at least 6)",
        ));
    }
    let s_max = bins.last().map(|b| b.0).unwrap_or(0.0);
    let peak = peak_bin(bins, peak_window)
        .map(|i| (bins[i - 1].1 + bins[i].1 + bins[i + 1].1) / 3.0)
        .unwrap_or(f64::NAN);
    if !peak.is_finite() {
        return Err(ChronoError::invalid(
            "peak_window",
            peak_window,
            "selects no bins",
        ));
    }
    let late: Vec<f64> = bins
        .iter()
        .filter(|b| b.0 >= (1.0 - residual_window) * s_max)
        .map(|b| b.1)
        .collect();
    if late.is_empty() {
        return Err(ChronoError::invalid(
            "residual_window",
            residual_window,
            "selects no bins",
        ));
    }
    Ok((peak, late.iter().sum::<f64>() / late.len() as f64))
}

/// Dilation rate `dy/dx` at bin `center`: the least-squares slope of the load plate's rise
/// `y` against the shear displacement `x` over the bins `(x, y)` within `half_width` of
/// displacement either side (same units for both, e.g. grain diameters). NaN outside the
/// bins or without spread.
///
/// Taylor's energy balance for the direct shear box: the shear work `S dx` is spent in
/// friction at the critical-state ratio `mu_cv` and in lifting the normal load,
/// `S dx = mu_cv N dx + N dy`, so the peak ratio is `S / N = mu_cv + dy/dx` at the peak's
/// dilation rate.
pub fn dilation_rate(bins: &[(f64, f64)], center: usize, half_width: f64) -> f64 {
    let Some(&(x0, _)) = bins.get(center) else {
        return f64::NAN;
    };
    let pts: Vec<(f64, f64)> = bins
        .iter()
        .copied()
        .filter(|(x, _)| (x - x0).abs() <= half_width + 1e-12)
        .collect();
    line_fit(&pts).map_or(f64::NAN, |(slope, _)| slope)
}

/// Taylor's balance along the whole curve: the mean of `S/N - dy/dx` over the bins at
/// displacement `x >= from`, with `dy/dx` the [`dilation_rate`] over `half_width` around
/// each bin. `ratio` and `rise` are bins `(x, S/N)` and `(x, y)` at the same displacements.
/// Where the energy balance `S dx = mu_cv N dx + N dy` holds, this is `mu_cv` whether the
/// sample dilates or contracts. NaN if no bin is at `x >= from`.
pub fn dilatancy_corrected_ratio(
    ratio: &[(f64, f64)],
    rise: &[(f64, f64)],
    from: f64,
    half_width: f64,
) -> f64 {
    let (mut sum, mut n) = (0.0, 0usize);
    for (i, &(x, r)) in ratio.iter().enumerate() {
        if x >= from {
            sum += r - dilation_rate(rise, i, half_width);
            n += 1;
        }
    }
    if n == 0 { f64::NAN } else { sum / n as f64 }
}

/// Dilation rate `dy/dx` over the residual window: the least-squares slope of the rise bins
/// `(x, y)` with `x >= (1 - residual_window) x_max`. Zero where the sample has reached its
/// critical state (steady volume); NaN with fewer than two bins there.
pub fn residual_dilation_rate(rise: &[(f64, f64)], residual_window: f64) -> f64 {
    let x_max = rise.last().map_or(0.0, |b| b.0);
    let late: Vec<(f64, f64)> = rise
        .iter()
        .copied()
        .filter(|b| b.0 >= (1.0 - residual_window) * x_max)
        .collect();
    line_fit(&late).map_or(f64::NAN, |(slope, _)| slope)
}
