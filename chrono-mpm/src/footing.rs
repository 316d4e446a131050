//! A rigid strip footing pushed into a weightless cohesive soil, in plane strain: the
//! bearing-capacity problem of Prandtl (1920).
//!
//! For a rigid-perfectly plastic Tresca soil of undrained shear strength `c_u`, weightless
//! and without surcharge, the limit pressure under a strip footing of width `B` (smooth or
//! rough: the mechanisms differ, the load does not for `phi = 0`) is
//!
//! ```text
//! q_u = (2 + pi) c_u          (Prandtl 1920; e.g. Terzaghi, Theoretical Soil Mechanics, 1943)
//! ```
//!
//! The soil here is von Mises clay ([`VonMises::from_undrained_strength`]): in plane strain
//! (with the out-of-plane stress at the mean of the in-plane ones, as an isochoric flow
//! gives) von Mises with `sigma_y = sqrt(3) c_u` has the same limit shear stress `c_u` as
//! Tresca, so the same `q_u`.
//!
//! The scene is half of the symmetric problem: the soil `x in [0, domain_width B]`,
//! `z in [0, domain_depth B]` (the Prandtl mechanism reaches `B` beyond the footing's edge
//! and about `0.7 B` deep), one cell thick in `y` between slip walls (plane strain, one
//! layer of markers); the plane `x = 0` is a
//! symmetry (slip) wall, the far side and the bottom are slip walls. The footing is a
//! sticky (rough) rigid box of half-width `B/2` centred on `x = 0`, its base on the soil's
//! surface, pushed down at `V(t) = speed r(t)` with the smooth ramp
//! `r = (1 - cos(pi t / t_ramp))/2` (see [`crate::compaction`]). The pressure is the
//! footing's reaction (the momentum it takes from the grid) over `B/2` times the slab's
//! thickness, averaged over each sampling interval. Gravity is off (weightless soil).
//!
//! [`VonMises::from_undrained_strength`]: crate::VonMises::from_undrained_strength

use nalgebra::Vector3;

use crate::body::{MpmBody, MpmSettings};
use crate::error::{Result, at_least, invalid, positive};
use crate::grid::{GridSpec, Wall};
use crate::material::{DruckerPrager, Material, VonMises};
use crate::pressure::{PressureSettings, box_slab_markers, slab_wall_markers};
use crate::rigid::{Contact, RigidBody, push_down, speed_ramp};

/// Parameters of the footing problem.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FootingSpec {
    /// Footing width `B`, m.
    pub footing_width: f64,
    /// Undrained shear strength `c_u` (the cohesion `c` with friction), Pa.
    pub cohesion: f64,
    /// Friction angle `phi`, degrees: 0 for the von Mises (Tresca-matched) clay, else
    /// Drucker–Prager matched to Mohr–Coulomb in plane strain
    /// ([`DruckerPrager::plane_strain`]).
    pub friction_angle_deg: f64,
    /// Young's modulus of the soil, Pa.
    pub young: f64,
    /// Poisson's ratio of the soil.
    pub poisson: f64,
    /// Density of the soil, kg/m^3 (inertia only: the soil is weightless).
    pub density: f64,
    /// Grid cells across the footing's half-width `B/2`.
    pub cells_half_width: usize,
    /// Markers per cell per axis.
    pub markers_per_cell: usize,
    /// Soil half-width from the symmetry plane, in footing widths `B`.
    pub domain_width: f64,
    /// Soil depth, in footing widths `B`.
    pub domain_depth: f64,
    /// The footing's final speed, m/s.
    pub speed: f64,
    /// Duration of the speed ramp, s.
    pub ramp_time: f64,
    /// Final settlement, in footing widths `B`.
    pub final_settlement: f64,
    /// CFL number of the time step.
    pub cfl: f64,
    /// F-bar volume averaging ([`crate::fbar`]).
    pub f_bar: crate::fbar::FBar,
}

impl FootingSpec {
    /// The limit pressure `c N_c`, Pa, of a weightless soil without surcharge:
    /// Prandtl–Reissner's `N_c = (N_q - 1) cot(phi)`, `N_q = exp(pi tan(phi))
    /// tan^2(pi/4 + phi/2)` (Prandtl 1920, Reissner 1924; e.g. Terzaghi, Theoretical Soil
    /// Mechanics, 1943, ch. VIII), `N_c = 2 + pi` at `phi = 0`. Exact for a
    /// rigid-perfectly plastic Mohr–Coulomb soil with associated flow.
    pub fn prandtl_pressure(&self) -> f64 {
        self.cohesion * bearing_factor_nc(self.friction_angle_deg)
    }
}

/// Prandtl–Reissner's bearing capacity factor `N_c` of friction angle `phi_deg` (degrees):
/// `(N_q - 1) cot(phi)` with `N_q = exp(pi tan(phi)) tan^2(pi/4 + phi/2)`; `2 + pi` at 0.
pub fn bearing_factor_nc(phi_deg: f64) -> f64 {
    let phi = phi_deg.to_radians();
    if phi.abs() < 1e-8 {
        return 2.0 + std::f64::consts::PI;
    }
    let nq = (std::f64::consts::PI * phi.tan()).exp()
        * (std::f64::consts::FRAC_PI_4 + 0.5 * phi).tan().powi(2);
    (nq - 1.0) / phi.tan()
}

/// One sample of the footing's load-settlement curve.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FootingSample {
    /// Time at the middle of the sampling interval, s.
    pub t: f64,
    /// Settlement at the middle of the interval, m.
    pub settlement: f64,
    /// Mean pressure under the footing over the interval, Pa.
    pub pressure: f64,
    /// Kinetic energy of the soil at the end of the interval, J.
    pub kinetic: f64,
    /// Elastic energy of the soil at the end of the interval, J.
    pub elastic: f64,
    /// Work done by the footing on the soil since the start, J.
    pub work: f64,
}

/// The footing and its soil.
#[derive(Clone, Debug)]
pub struct Footing {
    /// The MPM body (the footing is `body.rigid[0]`).
    pub body: MpmBody,
    spec: FootingSpec,
    /// The loaded area of the half model, `B/2` times the slab thickness, m^2.
    pub area: f64,
    z0: f64,
}

impl Footing {
    /// Builds the soil and the footing; errors name the field (`footing.*`,
    /// `material.*`).
    pub fn new(spec: FootingSpec) -> Result<Self> {
        let b = positive("footing.footing_width", spec.footing_width)?;
        positive("footing.density", spec.density)?;
        positive("footing.speed", spec.speed)?;
        positive("footing.cfl", spec.cfl)?;
        at_least(
            "footing.ramp_time",
            spec.ramp_time,
            0.0,
            "must be finite and >= 0",
        )?;
        at_least(
            "footing.domain_width",
            spec.domain_width,
            1.0,
            "must be >= 1 (footing widths)",
        )?;
        at_least(
            "footing.domain_depth",
            spec.domain_depth,
            0.5,
            "must be >= 0.5 (footing widths)",
        )?;
        if !(spec.final_settlement > 0.0 && spec.final_settlement < 0.5 * spec.domain_depth) {
            return Err(invalid(
                "footing.final_settlement",
                spec.final_settlement,
                "must lie in (0, domain_depth / 2) (footing widths)",
            ));
        }
        if spec.cells_half_width < 1 {
            return Err(invalid(
                "footing.cells_half_width",
                spec.cells_half_width,
                "must be >= 1",
            ));
        }
        if spec.markers_per_cell == 0 || spec.markers_per_cell > 8 {
            return Err(invalid(
                "footing.markers_per_cell",
                spec.markers_per_cell,
                "must lie in [1, 8]",
            ));
        }
        if !(spec.cohesion > 0.0 && spec.cohesion.is_finite()) {
            return Err(invalid(
                "material.cohesion",
                spec.cohesion,
                "must be finite and > 0 (a weightless soil without cohesion carries no load)",
            ));
        }
        let soil = if spec.friction_angle_deg == 0.0 {
            Material::VonMises(VonMises::from_undrained_strength(
                spec.young,
                spec.poisson,
                spec.cohesion,
            )?)
        } else {
            Material::DruckerPrager(DruckerPrager::plane_strain(
                spec.young,
                spec.poisson,
                spec.friction_angle_deg,
                spec.cohesion,
            )?)
        };
        let dx = 0.5 * b / spec.cells_half_width as f64;
        let nx = (spec.domain_width * b / dx).round() as usize;
        let nz = (spec.domain_depth * b / dx).round() as usize;
        let lz = nz as f64 * dx;
        // Room above the surface for the heave: a quarter of the depth plus 2 cells.
        let above = nz / 4 + 2;
        let grid = GridSpec::new([0.0; 3], [nx, 1, nz + above], dx)?
            .with_walls(0, Wall::Slip, Wall::Slip)
            .with_walls(1, Wall::Slip, Wall::Slip)
            .with_walls(2, Wall::Slip, Wall::Open);
        let settings = MpmSettings {
            gravity: [0.0; 3],
            cfl: spec.cfl,
            f_bar: spec.f_bar,
        };
        let mut body = MpmBody::new(grid, soil, settings)?;
        // Plane strain: one layer of markers across the slab (a second layer would only
        // repeat the first), `markers_per_cell` per axis in the plane.
        let d = dx / spec.markers_per_cell as f64;
        let (mx, mz) = (nx * spec.markers_per_cell, nz * spec.markers_per_cell);
        let vol = d * d * dx;
        for i in 0..mx {
            for k in 0..mz {
                let x = Vector3::new((i as f64 + 0.5) * d, 0.5 * dx, (k as f64 + 0.5) * d);
                body.markers
                    .push(spec.density * vol, vol, x, Vector3::zeros())?;
            }
        }
        // The footing: half-width B/2 about x = 0, as high as the room above, its base on
        // the surface; wider than the slab in y.
        let h = 0.5 * above as f64 * dx + dx;
        let z0 = lz + h;
        body.rigid.push(RigidBody::new_box(
            Vector3::new(0.0, 0.5 * dx, z0),
            [0.5 * b, dx, h],
            Vector3::zeros(),
            Contact::Sticky,
        )?);
        Ok(Self {
            body,
            spec,
            area: 0.5 * b * dx,
            z0,
        })
    }

    /// The parameters.
    pub fn spec(&self) -> &FootingSpec {
        &self.spec
    }

    /// Switches the soil to the split (`pressure = rows`, `docs/mpm.md` "The split"): the
    /// deviatoric stress by MPM, the pressure by density rows on the markers with the
    /// soil's bulk modulus as their compliance (`kappa = 1 / K`, `K = E / (3 (1 - 2 nu))`),
    /// wall markers beyond the floor and the two sides (the symmetry plane `x = 0` is a
    /// slip wall like the far side) and the footing's markers (its half `x > 0`, within
    /// `wall_layers` of its faces) moving with it; the rows' impulses on them add to the
    /// footing's reaction. `tolerance` is APGD's on the rows' velocity residual, m/s
    /// ([`PressureSettings::tolerance`]). Call before [`Footing::run`].
    pub fn use_pressure_rows(&mut self, tolerance: f64) -> Result<()> {
        let spec = self.spec;
        let grid = *self.body.spec();
        let dx = grid.dx;
        let d = dx / spec.markers_per_cell as f64;
        let settings = PressureSettings::plane_strain_soil(
            spec.density,
            spec.young,
            spec.poisson,
            d,
            tolerance,
        );
        let layers = chrono_core::particles::lattice::wall_layers(settings.h_over_dp);
        let width = grid.cells[0] as f64 * dx;
        let top = grid.cells[2] as f64 * dx;
        let walls = slab_wall_markers([0.0, width], [0.0, top], 0.5 * dx, d, layers, true, true)?;
        self.body.set_pressure_rows(settings, &walls)?;
        let footing = &self.body.rigid[0];
        let half = match footing.shape {
            crate::rigid::Shape::Box { half } => half,
            _ => return Err(invalid("footing.shape", "not a box", "must be a box")),
        };
        let local: Vec<[f64; 3]> = box_slab_markers([half[0], half[1], half[2]], 0.0, d, layers)?
            .into_iter()
            .filter(|l| footing.position.x + l[0] > 0.0)
            .collect();
        if let Some(rows) = self.body.pressure_rows_mut() {
            rows.attach_rigid(0, &local)?;
        }
        Ok(())
    }

    /// The settlement of the footing, m.
    pub fn settlement(&self) -> f64 {
        self.z0 - self.body.rigid[0].position.z
    }

    /// The footing's speed at time `t`, m/s (downwards positive).
    pub fn speed(&self, t: f64) -> f64 {
        self.spec.speed * speed_ramp(t, self.spec.ramp_time)
    }

    /// Runs to the final settlement with `samples` samples (at least 1); `progress` gets
    /// the fraction done.
    pub fn run(&mut self, samples: usize, progress: impl FnMut(f64)) -> Result<Vec<FootingSample>> {
        let (spec, z0) = (self.spec, self.z0);
        let settlement = |b: &MpmBody| z0 - b.rigid[0].position.z;
        let speed = |t: f64| spec.speed * speed_ramp(t, spec.ramp_time);
        let out = push_down(
            &mut self.body,
            self.area,
            spec.final_settlement * spec.footing_width,
            samples,
            settlement,
            speed,
            progress,
        )?;
        Ok(out
            .into_iter()
            .map(|s| FootingSample {
                t: s.t,
                settlement: s.measure,
                pressure: s.pressure,
                kinetic: s.kinetic,
                elastic: s.elastic,
                work: s.work,
            })
            .collect())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec() -> FootingSpec {
        FootingSpec {
            footing_width: 1.0,
            cohesion: 1e4,
            friction_angle_deg: 0.0,
            young: 5e6,
            poisson: 0.3,
            density: 1800.0,
            cells_half_width: 2,
            markers_per_cell: 2,
            domain_width: 2.5,
            domain_depth: 1.5,
            speed: 0.05,
            ramp_time: 0.2,
            final_settlement: 0.1,
            cfl: 0.4,
            f_bar: crate::fbar::FBar::Off,
        }
    }

    #[test]
    fn bad_footing_input_names_the_field() {
        let bad = |s: FootingSpec, field: &str| {
            let e = Footing::new(s).unwrap_err();
            assert!(e.to_string().contains(field), "{e} should name {field}");
        };
        let d = spec();
        bad(
            FootingSpec {
                cohesion: -1.0,
                ..d
            },
            "material.cohesion",
        );
        bad(FootingSpec { young: 0.0, ..d }, "material.young");
        bad(
            FootingSpec {
                footing_width: f64::NAN,
                ..d
            },
            "footing.footing_width",
        );
        bad(
            FootingSpec {
                final_settlement: 0.9,
                ..d
            },
            "footing.final_settlement",
        );
        bad(
            FootingSpec {
                cells_half_width: 0,
                ..d
            },
            "footing.cells_half_width",
        );
        bad(FootingSpec { speed: 0.0, ..d }, "footing.speed");
    }

    #[test]
    fn the_footing_starts_on_the_surface_and_pushes() {
        // A few steps: the footing's base starts on the soil's surface (no pressure
        // before it moves), then the soil resists it (positive pressure).
        let mut f = Footing::new(FootingSpec {
            final_settlement: 0.002,
            ramp_time: 0.0,
            ..spec()
        })
        .unwrap();
        assert_eq!(f.settlement(), 0.0);
        let top = f.body.markers.x.iter().map(|x| x.z).fold(0.0, f64::max);
        let base = f.body.rigid[0].position.z - f.body.rigid[0].shape.bounding_half()[2];
        assert!(base > top && base - top < f.body.spec().dx, "{base} {top}");
        let s = f.run(4, |_| {}).unwrap();
        assert!(s.iter().all(|s| s.pressure > 0.0), "{s:?}");
        assert!((f.spec().prandtl_pressure() - 51415.9).abs() < 0.1);
        // N_c of the tables (Terzaghi 1943, Prandtl-Reissner): 14.83 at 20 deg, 30.14 at
        // 30 deg, continuous at 0.
        assert!((bearing_factor_nc(20.0) - 14.835).abs() < 1e-3);
        assert!((bearing_factor_nc(30.0) - 30.140).abs() < 1e-3);
        assert!((bearing_factor_nc(1e-6) - (2.0 + std::f64::consts::PI)).abs() < 1e-4);
        let e = Footing::new(FootingSpec {
            friction_angle_deg: 95.0,
            ..spec()
        })
        .unwrap_err();
        assert!(e.to_string().contains("material.friction_angle_deg"), "{e}");
    }
}
