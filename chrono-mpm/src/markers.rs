//! MPM markers (material points), structure of arrays.

use nalgebra::{Matrix3, Vector3};

use crate::error::{Result, invalid, positive};

/// The markers of one MPM body: one entry per marker in each array.
#[derive(Clone, Debug, Default)]
pub struct Markers {
    /// Mass, kg.
    pub mass: Vec<f64>,
    /// Reference (initial) volume `V0`, m^3.
    pub volume0: Vec<f64>,
    /// Position, m.
    pub x: Vec<Vector3<f64>>,
    /// Velocity, m/s.
    pub v: Vec<Vector3<f64>>,
    /// APIC affine velocity matrix `C = B D^-1` (Jiang et al. 2015), 1/s: the marker
    /// carries the local velocity field `v(y) = v_p + C (y - x_p)`.
    pub c: Vec<Matrix3<f64>>,
    /// Elastic deformation gradient `F_E`.
    pub fe: Vec<Matrix3<f64>>,
    /// Plastic deformation gradient `F_P` (`F = F_E F_P`).
    pub fp: Vec<Matrix3<f64>>,
}

impl Markers {
    /// No markers.
    pub fn new() -> Self {
        Self::default()
    }

    /// Number of markers.
    pub fn len(&self) -> usize {
        self.mass.len()
    }

    /// Whether there are no markers.
    pub fn is_empty(&self) -> bool {
        self.mass.is_empty()
    }

    /// Adds an undeformed marker of `mass` (kg) and `volume0` (m^3) at `x` (m) with
    /// velocity `v` (m/s); returns its index. Errors name the field.
    pub fn push(
        &mut self,
        mass: f64,
        volume0: f64,
        x: Vector3<f64>,
        v: Vector3<f64>,
    ) -> Result<usize> {
        positive("marker.mass", mass)?;
        positive("marker.volume0", volume0)?;
        if !x.iter().all(|c| c.is_finite()) {
            return Err(invalid("marker.x", format!("{x:?}"), "must be finite"));
        }
        if !v.iter().all(|c| c.is_finite()) {
            return Err(invalid("marker.v", format!("{v:?}"), "must be finite"));
        }
        self.mass.push(mass);
        self.volume0.push(volume0);
        self.x.push(x);
        self.v.push(v);
        self.c.push(Matrix3::zeros());
        self.fe.push(Matrix3::identity());
        self.fp.push(Matrix3::identity());
        Ok(self.len() - 1)
    }

    /// Fills the box `[lo, hi]` (m) with markers of material `density` (kg/m^3) on a
    /// lattice of spacing `spacing` (m), cell-centred (the first marker at `lo + spacing/2`),
    /// each with volume `spacing^3` and velocity `velocity(x)`. Returns the index range of
    /// the new markers. The usual choice is `spacing = dx / 2` (8 markers per cell).
    pub fn fill_box(
        &mut self,
        lo: Vector3<f64>,
        hi: Vector3<f64>,
        spacing: f64,
        density: f64,
        velocity: impl Fn(&Vector3<f64>) -> Vector3<f64>,
    ) -> Result<std::ops::Range<usize>> {
        positive("fill.spacing", spacing)?;
        positive("fill.density", density)?;
        let mut n = [0usize; 3];
        for a in 0..3 {
            let ext = hi[a] - lo[a];
            if !(ext.is_finite() && ext > 0.0) {
                return Err(invalid(
                    &format!("fill.hi[{a}]"),
                    hi[a],
                    "must be finite and above fill.lo",
                ));
            }
            // Round so that an extent that is a multiple of the spacing (up to round-off)
            // fills exactly.
            n[a] = ((ext / spacing) + 1e-9).floor() as usize;
            if n[a] == 0 {
                return Err(invalid(
                    "fill.spacing",
                    spacing,
                    "is larger than the box to fill",
                ));
            }
        }
        let start = self.len();
        let vol = spacing.powi(3);
        for i in 0..n[0] {
            for j in 0..n[1] {
                for k in 0..n[2] {
                    let x =
                        lo + Vector3::new(i as f64 + 0.5, j as f64 + 0.5, k as f64 + 0.5) * spacing;
                    let v = velocity(&x);
                    self.push(density * vol, vol, x, v)?;
                }
            }
        }
        Ok(start..self.len())
    }
}
