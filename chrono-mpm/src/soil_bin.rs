//! A soil bin in plane strain: a layer of Drucker–Prager sand under gravity, at rest in its
//! geostatic state, the shared ground of the plate-sinkage test ([`crate::plate`]) and the
//! rigid wheel ([`crate::wheel`]).
//!
//! The layer `x in [0, length]`, `z in [0, depth]` is one cell thick in `y` between slip
//! walls (plane strain, one layer of markers). The bin's floor `z = 0` is sticky (a rough
//! bottom), its ends slip walls (smooth; `x = 0` is also the symmetry plane of a plate's
//! half model), the top open with room for the heave.
//!
//! **Geostatic start.** A layer released stress-free under gravity falls onto itself and
//! rings; instead every marker starts at the stress of a laterally confined elastic layer
//! under its own weight (uniaxial strain; Hencky elasticity, `tau = lambda tr(eps) I +
//! 2 mu eps` in the logarithmic strain `eps`):
//!
//! ```text
//! eps_zz = -rho g (depth - z) / (lambda + 2 mu),   F_E = diag(1, 1, exp(eps_zz))
//! tau_zz = -rho g (depth - z),   tau_xx = tau_yy = K0 tau_zz,   K0 = nu / (1 - nu)
//! ```
//!
//! (the weight above the marker per unit area in the reference configuration; `K0` is the
//! elastic earth-pressure coefficient, e.g. Wood, "Soil Behaviour and Critical State Soil
//! Mechanics", 1990, sec. 3.5). The state is inside the plane-strain cone whenever
//! `K0 >= (1 - sin phi)/(1 + sin phi)` (Rankine's active ratio), so for `nu = 0.3` up to
//! `phi` = 23.6 degrees exactly and beyond it after a small plastic correction the first
//! step makes. The markers sit on the undeformed lattice (the strain is 0.3 % at the
//! bottom of a 0.5 m layer with `E` = 2 MPa).

use nalgebra::{Matrix3, Vector3};

use crate::body::{MpmBody, MpmSettings};
use crate::error::{Result, invalid, positive};
use crate::grid::{GridSpec, Wall};
use crate::material::{DruckerPrager, Material};

/// Parameters of the sand and the bin.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SoilSpec {
    /// Friction angle `phi`, degrees, in (0, 90) (the plane-strain match
    /// [`DruckerPrager::plane_strain`]).
    pub friction_angle_deg: f64,
    /// Cohesion, Pa.
    pub cohesion: f64,
    /// Young's modulus, Pa.
    pub young: f64,
    /// Poisson's ratio, -.
    pub poisson: f64,
    /// Bulk density, kg/m^3.
    pub density: f64,
    /// Gravity `g`, m/s^2 (along `-z`; 0 is allowed: a weightless soil without initial
    /// stress).
    pub gravity: f64,
    /// Markers per cell per axis in the plane (one layer across the slab).
    pub markers_per_cell: usize,
    /// CFL number of the time step.
    pub cfl: f64,
    /// The FLIP fraction of the velocity update ([`MpmBody::set_flip`]; 0: APIC).
    pub flip: f64,
}

impl Default for SoilSpec {
    /// Loose dry sand of 30 degrees (the column collapse's, `crate::column`).
    fn default() -> Self {
        Self {
            friction_angle_deg: 30.0,
            cohesion: 0.0,
            young: 2e6,
            poisson: 0.3,
            density: 1500.0,
            gravity: 9.81,
            markers_per_cell: 2,
            cfl: 0.4,
            flip: 0.0,
        }
    }
}

impl SoilSpec {
    /// The sand; errors name the field (`material.*`, `soil.friction_angle_deg`).
    pub fn material(&self) -> Result<DruckerPrager> {
        if !(self.friction_angle_deg.is_finite()
            && self.friction_angle_deg > 0.0
            && self.friction_angle_deg < 90.0)
        {
            return Err(invalid(
                "soil.friction_angle_deg",
                self.friction_angle_deg,
                "must lie in (0, 90)",
            ));
        }
        DruckerPrager::plane_strain(
            self.young,
            self.poisson,
            self.friction_angle_deg,
            self.cohesion,
        )
    }

    /// Builds the bin: `length` by `depth` (m) of sand on a grid of spacing `dx` (m) with
    /// `room` (m) above the surface, the markers in their geostatic state (module
    /// documentation). Errors name the field (`soil.*`, `material.*`).
    pub fn build(&self, length: f64, depth: f64, room: f64, dx: f64) -> Result<MpmBody> {
        let dp = self.material()?;
        positive("soil.length", length)?;
        positive("soil.depth", depth)?;
        positive("soil.density", self.density)?;
        positive("soil.cfl", self.cfl)?;
        if !(self.gravity.is_finite() && self.gravity >= 0.0) {
            return Err(invalid(
                "soil.gravity",
                self.gravity,
                "must be finite and >= 0",
            ));
        }
        if !(room.is_finite() && room >= 0.0) {
            return Err(invalid("soil.room", room, "must be finite and >= 0"));
        }
        if self.markers_per_cell == 0 || self.markers_per_cell > 8 {
            return Err(invalid(
                "soil.markers_per_cell",
                self.markers_per_cell,
                "must lie in [1, 8]",
            ));
        }
        let nx = (length / dx).round().max(2.0) as usize;
        let nz = (depth / dx).round().max(2.0) as usize;
        let above = (room / dx).ceil() as usize + 2;
        let grid = GridSpec::new([0.0; 3], [nx, 1, nz + above], dx)?
            .with_walls(0, Wall::Slip, Wall::Slip)
            .with_walls(1, Wall::Slip, Wall::Slip)
            .with_walls(2, Wall::Sticky, Wall::Open);
        let settings = MpmSettings {
            gravity: [0.0, 0.0, -self.gravity],
            cfl: self.cfl,
            f_bar: crate::FBar::Off,
        };
        let mut body = MpmBody::new(grid, Material::DruckerPrager(dp), settings)?;
        body.set_flip(self.flip)?;
        let m = self.markers_per_cell;
        let d = dx / m as f64;
        let top = nz as f64 * dx;
        let vol = d * d * dx;
        let stiffness = dp.elastic.lambda + 2.0 * dp.elastic.mu;
        for i in 0..nx * m {
            for k in 0..nz * m {
                let z = (k as f64 + 0.5) * d;
                let x = Vector3::new((i as f64 + 0.5) * d, 0.5 * dx, z);
                let p = body
                    .markers
                    .push(self.density * vol, vol, x, Vector3::zeros())?;
                let eps = -self.density * self.gravity * (top - z) / stiffness;
                body.markers.fe[p] = Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, eps.exp()));
            }
        }
        Ok(body)
    }
}

/// The surface height of a bin built by [`SoilSpec::build`] with this `depth` and `dx`
/// (whole cells), m.
pub fn surface(depth: f64, dx: f64) -> f64 {
    (depth / dx).round().max(2.0) * dx
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn geostatic_layer_stays_at_rest() {
        // The initial stress balances gravity: after 200 steps the markers move at a
        // small fraction of the speed a layer released stress-free reaches,
        // g * (depth / c) (free fall for the time the wave needs to cross it).
        let soil = SoilSpec::default();
        let (depth, dx) = (0.4, 0.05);
        let mut body = soil.build(0.6, depth, 0.1, dx).unwrap();
        let mut free = body.clone();
        for mk in free.markers.fe.iter_mut() {
            *mk = Matrix3::identity();
        }
        let vmax = |b: &MpmBody| b.markers.v.iter().map(|v| v.norm()).fold(0.0, f64::max);
        for _ in 0..200 {
            let dt = 0.9 * body.stable_dt();
            body.step(dt).unwrap();
            free.step(dt).unwrap();
        }
        let (v, v_free) = (vmax(&body), vmax(&free));
        assert!(
            v < 0.1 * v_free,
            "geostatic {v} m/s, stress-free {v_free} m/s"
        );
    }

    #[test]
    fn bad_soil_input_names_the_field() {
        let e = SoilSpec {
            friction_angle_deg: 0.0,
            ..SoilSpec::default()
        }
        .build(1.0, 1.0, 0.1, 0.1)
        .unwrap_err();
        assert!(e.to_string().contains("soil.friction_angle_deg"), "{e}");
        let e = SoilSpec {
            gravity: f64::NAN,
            ..SoilSpec::default()
        }
        .build(1.0, 1.0, 0.1, 0.1)
        .unwrap_err();
        assert!(e.to_string().contains("soil.gravity"), "{e}");
    }
}
