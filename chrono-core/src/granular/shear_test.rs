//! The direct shear test: grains poured into a [`ShearBox`], consolidated under the load
//! plate, then sheared at constant speed, the force ratio `S / N` and the plate's rise read
//! in bins of displacement and reduced to a peak, a residual and dilation rates
//! ([`ShearTest`], [`ShearRun`]), on a system the caller made (contact method, solver,
//! settings).
//!
//! The setup follows J. Härtl and J. Y. Ooi, "Experiments and simulations of direct shear
//! tests: porosity, contact friction and bulk friction", Granular Matter 10 (2008) 263–271,
//! and J. Fleischmann, R. Serban, D. Negrut and P. Jayakumar, "On the importance of
//! displacement history in soft-body contact models", J. Comput. Nonlinear Dynam. 11
//! (2016) 044502 (6 mm glass beads, a 20 d box, normal stresses of 3–24 kPa). The reduction
//! and Taylor's energy balance `S / N = mu_cv + dy/dx` are in [`super::shear_box`].

use nalgebra::Vector3;

use super::bed::{Bed, GrainBed, Kick, Settle};
use super::fill::Region;
use super::probe::{max_penetration, uniaxial_overlap_strain};
use super::shear_box::{
    ShearBox, ShearBoxBodies, dilatancy_corrected_ratio, dilation_rate, peak_and_residual,
    peak_bin, residual_dilation_rate,
};
use super::step_size;
use crate::error::{ChronoError, Result, check_non_negative, check_positive};
use crate::material::ContactMaterial;
use crate::system::{ContactMethod, FrictionLaw, System, SystemSettings};

/// Solid fraction assumed for the settled sample when sizing its grain count.
pub const SETTLED_FRACTION: f64 = 0.6;

/// Start (in grain diameters of displacement) of the bins over which Taylor's balance is
/// averaged along the curve ([`ShearRun::balance`]): past the initial elastic rise of the
/// ratio.
pub const BALANCE_FROM: f64 = 0.3;

/// The salt of the bed's kick (its random horizontal velocities).
const KICK_SALT: u64 = 0x5bd1_e995;

/// A direct shear test on mono-disperse grains of diameter `d` (Z up, shear along +x, the
/// shear plane at `z = 0`): grains poured into a [`ShearBox`] from a jittered lattice
/// (sites 1.25 d apart) holding the number that fills twice `half_height` at
/// [`SETTLED_FRACTION`], settled under gravity for `t_settle`; the load plate put on the
/// sample with `normal_stress length^2` in all for `t_consolidate`; the lower half then
/// driven at `shear_speed` over `displacement`, the forces averaged over bins of `bin` of
/// displacement.
///
/// The plate weighs about one layer of grains (`SETTLED_FRACTION density side^2 d`):
/// heavy enough to stay flat under the grains' impacts, light enough not to strain an NSC
/// solve (the load is an applied force). The box's walls, floor and plate are `d` thick;
/// the plate is `0.2 d` narrower than the box.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShearTest {
    /// Grain diameter `d`, m.
    pub grain_diameter: f64,
    /// Inner side of the square box, m.
    pub length: f64,
    /// Depth of the lower half below the shear plane, m (the sample is about twice as
    /// high).
    pub half_height: f64,
    /// Gap between the two halves, m (below `d`: no grain passes).
    pub gap: f64,
    /// Grain density, kg/m^3.
    pub density: f64,
    /// Contact material of the grains.
    pub grain_material: ContactMaterial,
    /// Contact material of the box and the plate.
    pub wall_material: ContactMaterial,
    /// Seed of the packing (jitter, kick).
    pub seed: u64,
    /// Sliding friction of every grain contact while the grains settle (no rolling or
    /// spinning friction), restored to the materials' before the load: sets the sample's
    /// density (0: dense; `None`: settle with the materials).
    pub settle_friction: Option<f64>,
    /// Cap on the solver's iterations while the grains settle (the pour only has to make a
    /// packing), restored before the load; `None`: the solver's own cap throughout.
    pub settle_iterations: Option<usize>,
    /// Friction law once the sample is loaded (`None`: the system's own).
    pub loaded_friction_law: Option<FrictionLaw>,
    /// Normal stress `sigma` on the sample, Pa: the load is `sigma length^2`.
    pub normal_stress: f64,
    /// Speed of the lower half, m/s.
    pub shear_speed: f64,
    /// Shear displacement, in grain diameters.
    pub displacement: f64,
    /// Width of the averaging bins, in grain diameters of displacement.
    pub bin: f64,
    /// Settling time before the load, s.
    pub t_settle: f64,
    /// Consolidation time under the load before shearing, s.
    pub t_consolidate: f64,
    /// Time step, s (0: [`step_size`]'s, 1 ms for NSC, the SMC stability limit for SMC).
    pub h: f64,
    /// Fraction of the displacement (from the start) searched for the peak
    /// ([`peak_and_residual`]).
    pub peak_window: f64,
    /// Fraction of the displacement (at the end) averaged for the residual.
    pub residual_window: f64,
    /// Half width of the displacement window (in grain diameters) of the dilation rate
    /// ([`dilation_rate`]).
    pub dilation_window: f64,
}

/// One bin of a shear test's read-out (forces averaged over the bin's steps).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ShearBin {
    /// Shear displacement at the bin's end, in grain diameters.
    pub displacement: f64,
    /// `S / N`: the shear force the grains exert on the upper half and the plate over the
    /// normal force on the shear plane (their vertical force plus the weight of the grains
    /// above the plane).
    pub ratio: f64,
    /// `S / (sigma length^2)`: the shear force over the applied load.
    pub applied_ratio: f64,
    /// Rise of the load plate since the shear started, in grain diameters.
    pub rise: f64,
    /// `-S_lower / S`: the lower half's shear force over the upper's (1 when quasi-static).
    pub halves: f64,
}

/// Means over the shear steps of the step's CCP solves (NSC; zeros for SMC).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SolveMeans {
    /// Solver iterations per step (summed over the Coulomb passes).
    pub iterations: f64,
    /// Fraction of steps whose (last) solve reached the tolerance.
    pub converged: f64,
    /// Residual of the (last) solve, m/s.
    pub residual: f64,
    /// Friction re-solves per step (0 for the relaxed cone).
    pub passes: f64,
}

/// What a shear test measured.
#[derive(Debug, Clone, PartialEq)]
pub struct ShearRun {
    /// The system's contact method.
    pub method: ContactMethod,
    /// The read-out, by bin of increasing displacement.
    pub bins: Vec<ShearBin>,
    /// Peak of `S / N` ([`peak_and_residual`]).
    pub peak: f64,
    /// Residual of `S / N` (mean over the residual window).
    pub residual: f64,
    /// Dilation rate `dy/dx` of the load plate at the peak ([`dilation_rate`]).
    pub peak_dilation: f64,
    /// Dilation rate `dy/dx` of the load plate over the residual window
    /// ([`residual_dilation_rate`]).
    pub residual_dilation: f64,
    /// `S/N - dy/dx` averaged over the bins from [`BALANCE_FROM`] on
    /// ([`dilatancy_corrected_ratio`]): `mu_cv` where Taylor's balance holds.
    pub balance: f64,
    /// The solves over the shear steps.
    pub solve: SolveMeans,
    /// Grains in the box.
    pub grains: usize,
    /// Steps taken.
    pub steps: u64,
    /// Time step, s.
    pub h: f64,
    /// Weight of the grains above the shear plane over the applied load, mean over the
    /// bins.
    pub self_weight: f64,
    /// Kinetic energy per grain when the load is applied, in units of `m g d`.
    pub ke_settled: f64,
    /// Solid fraction of the consolidated sample before the shear: the grains' volume over
    /// the box's between the floor and the plate (walls included, so below the bulk value;
    /// it compares preparations).
    pub solid_fraction: f64,
    /// Elastic vertical strain of the consolidated sample from its contact overlaps
    /// ([`uniaxial_overlap_strain`]).
    pub overlap_strain: f64,
    /// Grains below the floor's top at the end (fallen out through the opening the lower
    /// half leaves under the upper one's trailing side).
    pub escaped: usize,
    /// Deepest penetration (NSC) or overlap (SMC) of the last step, in grain diameters.
    pub penetration: f64,
}

impl ShearRun {
    /// The consolidated sample's solid fraction with its elastic compression removed,
    /// `solid_fraction (1 - overlap_strain)`: the packing with rigid grains.
    pub fn rigid_solid_fraction(&self) -> f64 {
        self.solid_fraction * (1.0 - self.overlap_strain)
    }

    /// The residual angle, degrees: `atan(S/N - dy/dx)` with Taylor's correction for the
    /// work of lifting the load where the sample still dilates over the residual window (a
    /// box too short for a dense sample to reach its critical state); a contracting
    /// sample's ratio is taken as it is (Bolton's relative dilatancy index `I_R <= 0`).
    pub fn residual_deg(&self) -> f64 {
        (self.residual - self.residual_dilation.max(0.0))
            .atan()
            .to_degrees()
    }
}

impl ShearTest {
    /// A direct shear test of glass beads of diameter `d` after Härtl and Ooi (Granular
    /// Matter 10, 2008; the set-up of xtask's `granular-shear`), one `material` for grains
    /// and walls: box side `20 d`, lower half `5.5 d` deep, gap `0.5 d`, 3.1 kPa, 5 mm/s, density
    /// 2550 kg/m^3, seed 7, settled 0.4 s and consolidated 0.1 s with the materials,
    /// sheared over `1.5 d` read in bins of `0.05 d`, the step size from [`step_size`];
    /// the peak searched over the whole curve, the residual over its last 30 %, the
    /// dilation rate over `+-0.15 d`. Change any field with struct update syntax.
    pub fn new(grain_diameter: f64, material: ContactMaterial) -> Self {
        let d = grain_diameter;
        Self {
            grain_diameter: d,
            length: 20.0 * d,
            half_height: 5.5 * d,
            gap: 0.5 * d,
            density: 2550.0,
            grain_material: material,
            wall_material: material,
            seed: 7,
            settle_friction: None,
            settle_iterations: None,
            loaded_friction_law: None,
            normal_stress: 3.1e3,
            shear_speed: 0.005,
            displacement: 1.5,
            bin: 0.05,
            t_settle: 0.4,
            t_consolidate: 0.1,
            h: 0.0,
            peak_window: 1.0,
            residual_window: 0.3,
            dilation_window: 0.15,
        }
    }

    /// Errors naming the field (`shear_test.*`) unless the test can run.
    pub fn validate(&self) -> Result<()> {
        for (field, v) in [
            ("shear_test.grain_diameter", self.grain_diameter),
            ("shear_test.density", self.density),
            ("shear_test.normal_stress", self.normal_stress),
            ("shear_test.shear_speed", self.shear_speed),
            ("shear_test.displacement", self.displacement),
            ("shear_test.bin", self.bin),
        ] {
            check_positive(field, v)?;
        }
        check_non_negative("shear_test.t_settle", self.t_settle)?;
        check_non_negative("shear_test.t_consolidate", self.t_consolidate)?;
        check_non_negative("shear_test.h", self.h)?;
        if !(self.gap >= 0.0 && self.gap < self.grain_diameter) {
            return Err(ChronoError::invalid(
                "shear_test.gap",
                self.gap,
                format!(
                    "must be in [0, grain_diameter = {}): grains would pass between the halves",
                    self.grain_diameter
                ),
            ));
        }
        self.grain_material.validate()?;
        self.wall_material.validate()
    }

    /// Adds the box ([`ShearBox::add`]) to `sys` (an empty system the caller made: contact
    /// method, solver, settings) and pours the grains; the step is fixed once they are in
    /// (SMC's stability limit depends on them). An error names `bed.count` when the box
    /// cannot hold the grains.
    pub fn build(&self, sys: &mut System) -> Result<ShearScene> {
        self.validate()?;
        let d = self.grain_diameter;
        let r = 0.5 * d;
        let (l, hl, gap, t) = (self.length, self.half_height, self.gap, d);
        // The grains: a jittered lattice (sites 1.25 d apart) holding the number that fills
        // 2 `half_height` at the settled solid fraction.
        let v_grain = std::f64::consts::PI / 6.0 * d.powi(3);
        let count = (SETTLED_FRACTION * l * l * 2.0 * hl / v_grain).round() as usize;
        let pitch = d + 0.5 * r;
        let per_layer = ((l / pitch).floor() as usize).pow(2).max(1);
        let layers = count.div_ceil(per_layer) as f64;
        let fill_top = -hl + (layers + 1.0) * pitch;
        let z_top = fill_top + d;
        let side = l - 0.2 * d;
        let shear_box = ShearBox {
            length: l,
            half_height: hl,
            gap,
            wall: t,
            top: z_top,
            plate_clearance: 0.2 * d,
            plate_mass: SETTLED_FRACTION * self.density * side * side * t,
            material: self.wall_material,
        };
        let bodies = shear_box.add(sys)?;
        let spec = GrainBed {
            count: Some(count),
            seed: self.seed,
            // Random horizontal velocities break the lattice's columns.
            kick: Some(Kick {
                speed: 0.1,
                salt: KICK_SALT,
            }),
            settle_friction: self.settle_friction,
            ..GrainBed::new(
                Region::Box {
                    lower: Vector3::new(-0.5 * l, -0.5 * l, -hl),
                    upper: Vector3::new(0.5 * l, 0.5 * l, fill_top),
                },
                r,
                r,
                self.density,
                self.grain_material,
            )
        };
        let bed = spec.pour(sys)?;
        let h = step_size(self.h, sys.settings().contact_method, sys);
        Ok(ShearScene {
            test: *self,
            shear_box,
            bodies,
            spec,
            bed,
            h,
            v_grain,
            z_top,
        })
    }
}

/// A built shear test: the box, the poured grains and the step.
#[derive(Debug, Clone)]
pub struct ShearScene {
    test: ShearTest,
    shear_box: ShearBox,
    bodies: ShearBoxBodies,
    spec: GrainBed,
    bed: Bed,
    h: f64,
    v_grain: f64,
    z_top: f64,
}

impl ShearScene {
    /// The time step, s.
    pub fn h(&self) -> f64 {
        self.h
    }

    /// The box.
    pub fn shear_box(&self) -> &ShearBox {
        &self.shear_box
    }

    /// The box's bodies.
    pub fn bodies(&self) -> &ShearBoxBodies {
        &self.bodies
    }

    /// The poured grains.
    pub fn bed(&self) -> &Bed {
        &self.bed
    }

    /// Steps of each phase: settling, consolidation, steps per bin and bins.
    fn phases(&self) -> (u64, u64, u64, u64) {
        let (p, h, d) = (&self.test, self.h, self.test.grain_diameter);
        (
            (p.t_settle / h).round().max(1.0) as u64,
            (p.t_consolidate / h).round().max(1.0) as u64,
            ((p.bin * d / (p.shear_speed * h)).round() as u64).max(1),
            (p.displacement / p.bin).round().max(1.0) as u64,
        )
    }

    /// Steps of the whole test.
    pub fn total_steps(&self) -> u64 {
        let (n_settle, n_cons, per_bin, n_bins) = self.phases();
        n_settle + n_cons + n_bins * per_bin
    }

    /// Settles, loads, consolidates and shears the sample, calling `on_step(sys, step)`
    /// after each step (step counted from 1 to [`ShearScene::total_steps`]; VTK frames,
    /// progress). Errors name `shear_test.half_height` when grains are above the box after
    /// settling, `shear_test.normal_stress` when the shear plane carries no normal force,
    /// and the windows that select no bins ([`peak_and_residual`]).
    pub fn run<E: From<ChronoError>>(
        &mut self,
        sys: &mut System,
        mut on_step: impl FnMut(&mut System, u64) -> std::result::Result<(), E>,
    ) -> std::result::Result<ShearRun, E> {
        let (p, h, d) = (self.test, self.h, self.test.grain_diameter);
        let r = 0.5 * d;
        let (l, hl) = (p.length, p.half_height);
        let (shear_box, bodies) = (self.shear_box, self.bodies);
        let handles = self.bed.handles.clone();
        let g = sys.settings().gravity.norm();
        let grain_mass = sys.body(handles[0])?.mass();
        let structure = bodies.structure();
        let (n_settle, n_cons, steps_per_bin, n_bins) = self.phases();
        let n_total = self.total_steps();
        let full_iterations = sys.solver_mut().settings_mut().max_iterations;
        if let Some(cap) = p.settle_iterations {
            sys.solver_mut().settings_mut().max_iterations = full_iterations.min(cap);
        }
        let settled = GrainBed {
            settle: Settle::Steps(n_settle),
            ..self.spec
        }
        .settle(sys, &self.bed, h, &mut on_step)?;
        let mut step = settled.steps;
        sys.solver_mut().settings_mut().max_iterations = full_iterations;
        if let Some(law) = p.loaded_friction_law {
            sys.set_settings(SystemSettings {
                friction_law: law,
                ..sys.settings().clone()
            })?;
        }
        let ke_settled = sys.kinetic_energy() / handles.len() as f64 / (grain_mass * g * d);
        // Load: the plate just above the highest grain, pushing with sigma L^2 in all.
        let mut top = f64::NEG_INFINITY;
        for &b in &handles {
            top = top.max(sys.body(b)?.position().z + r);
        }
        if top.is_nan() || top >= self.z_top {
            return Err(ChronoError::invalid(
                "shear_test.half_height",
                hl,
                format!(
                    "grains above the box after settling (top {top} m, walls end at {} m)",
                    self.z_top
                ),
            )
            .into());
        }
        let load = p.normal_stress * l * l;
        shear_box.load(sys, &bodies, top, 0.02 * d, load)?;
        for _ in 0..n_cons {
            sys.step(h)?;
            step += 1;
            on_step(sys, step)?;
        }
        let z_plate0 = sys.body(bodies.plate)?.position().z;
        let solid_fraction =
            handles.len() as f64 * self.v_grain / shear_box.sample_volume(sys, &bodies)?;
        let overlap_strain = uniaxial_overlap_strain(sys, &structure)?;
        shear_box.drive(sys, &bodies, p.shear_speed)?;
        let z_plane = 0.5 * p.gap;
        let x0 = sys.body(bodies.lower)?.position().x;
        let (mut bins, mut weight_sum) = (Vec::with_capacity(n_bins as usize), 0.0);
        let mut solve = SolveMeans::default();
        for _ in 0..n_bins {
            let (mut f, mut f_lower) = (Vector3::zeros(), Vector3::zeros());
            for _ in 0..steps_per_bin {
                let rep = sys.step(h)?;
                solve.iterations += rep.solve.iterations as f64;
                solve.converged += f64::from(u8::from(rep.solve.converged));
                solve.residual += rep.solve.residual;
                solve.passes += rep.friction_passes as f64;
                step += 1;
                let (on_upper, on_lower) = shear_box.grain_forces(sys, &bodies, h);
                f += on_upper;
                f_lower += on_lower;
                on_step(sys, step)?;
            }
            f /= steps_per_bin as f64;
            let mut above = 0usize;
            for &b in &handles {
                if sys.body(b)?.position().z > z_plane {
                    above += 1;
                }
            }
            let weight = above as f64 * grain_mass * g;
            weight_sum += weight / load;
            let normal = f.z + weight;
            if normal <= 0.0 || normal.is_nan() {
                return Err(ChronoError::invalid(
                    "shear_test.normal_stress",
                    p.normal_stress,
                    format!("no normal force on the shear plane ({normal} N) at step {step}"),
                )
                .into());
            }
            bins.push(ShearBin {
                displacement: (sys.body(bodies.lower)?.position().x - x0) / d,
                ratio: f.x / normal,
                applied_ratio: f.x / load,
                rise: (sys.body(bodies.plate)?.position().z - z_plate0) / d,
                // Quasi-static: the lower half feels the opposite shear force.
                halves: -f_lower.x / steps_per_bin as f64 / f.x,
            });
        }
        let pairs: Vec<(f64, f64)> = bins.iter().map(|b| (b.displacement, b.ratio)).collect();
        let (peak, residual) = peak_and_residual(&pairs, p.peak_window, p.residual_window)?;
        let rise: Vec<(f64, f64)> = bins.iter().map(|b| (b.displacement, b.rise)).collect();
        let balance = dilatancy_corrected_ratio(&pairs, &rise, BALANCE_FROM, p.dilation_window);
        let peak_dilation = peak_bin(&pairs, p.peak_window)
            .map_or(f64::NAN, |i| dilation_rate(&rise, i, p.dilation_window));
        let mut escaped = 0usize;
        for &b in &handles {
            if sys.body(b)?.position().z < -hl - r {
                escaped += 1;
            }
        }
        let n = (n_bins * steps_per_bin) as f64;
        Ok(ShearRun {
            method: sys.settings().contact_method,
            self_weight: weight_sum / n_bins as f64,
            ke_settled,
            solid_fraction,
            overlap_strain,
            penetration: max_penetration(sys) / d,
            escaped,
            bins,
            peak,
            residual,
            peak_dilation,
            residual_dilation: residual_dilation_rate(&rise, p.residual_window),
            balance,
            solve: SolveMeans {
                iterations: solve.iterations / n,
                converged: solve.converged / n,
                residual: solve.residual / n,
                passes: solve.passes / n,
            },
            grains: handles.len(),
            steps: n_total,
            h,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn test_spec() -> ShearTest {
        ShearTest::new(0.006, ContactMaterial::smc(4e7, 0.22, 0.87, 0.18))
    }

    #[test]
    fn bad_fields_are_named() {
        assert!(test_spec().validate().is_ok());
        let e = ShearTest {
            gap: 0.01,
            ..test_spec()
        }
        .validate()
        .unwrap_err()
        .to_string();
        assert!(e.contains("shear_test.gap") && e.contains("0.01"), "{e}");
        let e = ShearTest {
            normal_stress: -1.0,
            ..test_spec()
        }
        .validate()
        .unwrap_err()
        .to_string();
        assert!(e.contains("shear_test.normal_stress"), "{e}");
    }

    #[test]
    fn residual_angle_corrects_only_dilation() {
        let run = |residual_dilation| ShearRun {
            method: ContactMethod::Smc,
            bins: Vec::new(),
            peak: 0.6,
            residual: 0.5,
            peak_dilation: 0.1,
            residual_dilation,
            balance: 0.45,
            solve: SolveMeans::default(),
            grains: 0,
            steps: 0,
            h: 1e-4,
            self_weight: 0.0,
            ke_settled: 0.0,
            solid_fraction: 0.6,
            overlap_strain: 0.01,
            escaped: 0,
            penetration: 0.0,
        };
        let dilating = run(0.05).residual_deg();
        assert!((dilating - 0.45f64.atan().to_degrees()).abs() < 1e-12);
        let contracting = run(-0.05).residual_deg();
        assert!((contracting - 0.5f64.atan().to_degrees()).abs() < 1e-12);
        assert!((run(0.0).rigid_solid_fraction() - 0.594).abs() < 1e-12);
    }
}
