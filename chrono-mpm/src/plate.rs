//! Plate sinkage on the MPM sand and Bekker's pressure–sinkage law fitted to it (Bekker,
//! "Theory of Land Locomotion", 1956; Wong, "Theory of Ground Vehicles", 4th ed., Wiley
//! 2008, sec. 2.4):
//!
//! ```text
//! p = (k_c / b + k_phi) z^n
//! ```
//!
//! with `p` the plate pressure (Pa), `z` the sinkage (m), `b` the plate's smaller
//! dimension (m), `k_c` (N/m^(n+1)), `k_phi` (N/m^(n+2)) and `n` (-) fitted to plates of
//! two widths: `n` the common slope of `log p` against `log z`, `K(b) = k_c/b + k_phi` the
//! intercept per width, `k_c = (K_1 - K_2) / (1/b_1 - 1/b_2)`, `k_phi = K_1 - k_c / b_1`
//! (Wong sec. 2.4.1, the procedure with two plate sizes).
//!
//! The plate here is a strip of width `b` in plane strain (a long plate: `b` its smaller
//! dimension), rough (sticky), pushed into the soil bin ([`crate::soil_bin`]) at a slow
//! constant speed after a smooth ramp; half the problem by symmetry (the bin's slip wall
//! `x = 0`). The pressure is the plate's reaction over its area, averaged over each
//! sampling interval.
//!
//! Bekker's (Wong's) rigid-wheel static sinkage from the fitted law, for a towed rigid
//! wheel of diameter `D` and width `b` under a vertical load `W` (Wong eq. 2.64, the
//! pressure under the rim taken as the plate's at the same depth, the rim in contact on the
//! front arc only):
//!
//! ```text
//! z_0 = [ 3 W / ((3 - n)(k_c + b k_phi) sqrt(D)) ]^(2 / (2n + 1))
//! ```

use nalgebra::Vector3;

use crate::body::MpmBody;
use crate::error::{Result, at_least, invalid, positive};
use crate::rigid::{Contact, RigidBody, push_down, speed_ramp};
use crate::soil_bin::{SoilSpec, surface};

/// Parameters of a plate-sinkage run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlateSpec {
    /// The sand.
    pub soil: SoilSpec,
    /// Plate width `b`, m.
    pub plate_width: f64,
    /// Grid spacing, m.
    pub dx: f64,
    /// Soil half-width from the symmetry plane, in plate widths.
    pub domain_width: f64,
    /// Soil depth, in plate widths.
    pub domain_depth: f64,
    /// Final sinkage, m.
    pub final_sinkage: f64,
    /// Plate speed, m/s.
    pub speed: f64,
    /// Duration of the speed ramp, s.
    pub ramp_time: f64,
}

/// One sample of a plate-sinkage curve.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlateSample {
    /// Sinkage at the middle of the sampling interval, m.
    pub sinkage: f64,
    /// Mean plate pressure over the interval, Pa.
    pub pressure: f64,
}

/// A plate pushed into the soil bin.
#[derive(Clone, Debug)]
pub struct Plate {
    /// The MPM body (the plate is `body.rigid[0]`).
    pub body: MpmBody,
    spec: PlateSpec,
    z0: f64,
}

impl Plate {
    /// Builds the bin and the plate on its surface; errors name the field (`plate.*`,
    /// `soil.*`, `material.*`).
    pub fn new(spec: PlateSpec) -> Result<Self> {
        let b = positive("plate.plate_width", spec.plate_width)?;
        let dx = positive("plate.dx", spec.dx)?;
        positive("plate.speed", spec.speed)?;
        at_least(
            "plate.ramp_time",
            spec.ramp_time,
            0.0,
            "must be finite and >= 0",
        )?;
        if 0.5 * b < dx {
            return Err(invalid(
                "plate.plate_width",
                b,
                "must span at least two cells (half-width >= dx)",
            ));
        }
        at_least(
            "plate.domain_width",
            spec.domain_width,
            1.0,
            "must be >= 1 (plate widths)",
        )?;
        at_least(
            "plate.domain_depth",
            spec.domain_depth,
            0.5,
            "must be >= 0.5 (plate widths)",
        )?;
        let depth = spec.domain_depth * b;
        if !(spec.final_sinkage > 0.0 && spec.final_sinkage < 0.5 * depth) {
            return Err(invalid(
                "plate.final_sinkage",
                spec.final_sinkage,
                "must lie in (0, domain_depth b / 2) m",
            ));
        }
        let room = spec.final_sinkage + 2.0 * dx;
        let mut body = spec.soil.build(spec.domain_width * b, depth, room, dx)?;
        let top = surface(depth, dx);
        // The plate: half-width b/2 about x = 0, as high as the room above, its base on the
        // surface; wider than the slab in y.
        let h = 0.5 * room + dx;
        let z0 = top + h;
        body.rigid.push(RigidBody::new_box(
            Vector3::new(0.0, 0.5 * dx, z0),
            [0.5 * b, dx, h],
            Vector3::zeros(),
            Contact::Sticky,
        )?);
        Ok(Self { body, spec, z0 })
    }

    /// The parameters.
    pub fn spec(&self) -> &PlateSpec {
        &self.spec
    }

    /// The plate's sinkage below the initial surface, m.
    pub fn sinkage(&self) -> f64 {
        self.z0 - self.body.rigid[0].position.z
    }

    /// Pushes the plate to [`PlateSpec::final_sinkage`]; `samples` samples; `progress`
    /// gets the fraction done. Errors: a diverging run (naming the marker and the step).
    pub fn run(&mut self, samples: usize, progress: impl FnMut(f64)) -> Result<Vec<PlateSample>> {
        let (v, tr) = (self.spec.speed, self.spec.ramp_time);
        let area = 0.5 * self.spec.plate_width * self.body.spec().dx;
        let z0 = self.z0;
        let out = push_down(
            &mut self.body,
            area,
            self.spec.final_sinkage,
            samples,
            |b| z0 - b.rigid[0].position.z,
            |t| v * speed_ramp(t, tr),
            progress,
        )?;
        Ok(out
            .into_iter()
            .map(|s| PlateSample {
                sinkage: s.measure,
                pressure: s.pressure,
            })
            .collect())
    }
}

/// Bekker's pressure–sinkage parameters (module documentation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bekker {
    /// Cohesive modulus `k_c`, N/m^(n+1).
    pub k_c: f64,
    /// Frictional modulus `k_phi`, N/m^(n+2).
    pub k_phi: f64,
    /// Sinkage exponent `n`, -.
    pub n: f64,
    /// Root-mean-square residual of `ln p` over the fitted samples, -.
    pub rms_log: f64,
}

impl Bekker {
    /// The plate pressure at sinkage `z` (m) for width `b` (m), Pa.
    pub fn pressure(&self, b: f64, z: f64) -> f64 {
        (self.k_c / b + self.k_phi) * z.powf(self.n)
    }

    /// Fits `p = (k_c/b + k_phi) z^n` to two plates' samples `(b, samples)`, over the
    /// samples with sinkage in `[z_lo, z_hi]` (m) and positive pressure: least squares of
    /// `ln p = ln K_j + n ln z` with one `n` and one intercept per plate, then `k_c`,
    /// `k_phi` from the two intercepts. Errors name `plate_widths` (equal widths) or
    /// `fit_range` (fewer than two samples per plate in the range).
    pub fn fit(plates: [(f64, &[PlateSample]); 2], z_lo: f64, z_hi: f64) -> Result<Self> {
        let (b1, b2) = (plates[0].0, plates[1].0);
        if !(b1 > 0.0 && b2 > 0.0 && (b1 - b2).abs() > 1e-12 * b1.max(b2)) {
            return Err(invalid(
                "plate_widths",
                format!("[{b1}, {b2}]"),
                "must be two different positive widths",
            ));
        }
        let pts: [Vec<(f64, f64)>; 2] = std::array::from_fn(|j| {
            plates[j]
                .1
                .iter()
                .filter(|s| s.sinkage >= z_lo && s.sinkage <= z_hi && s.pressure > 0.0)
                .map(|s| (s.sinkage.ln(), s.pressure.ln()))
                .collect()
        });
        if pts.iter().any(|p| p.len() < 2) {
            return Err(invalid(
                "fit_range",
                format!("[{z_lo}, {z_hi}] m"),
                "holds fewer than two samples of a plate",
            ));
        }
        // Common slope: the pooled within-plate regression.
        let mean = |p: &[(f64, f64)]| {
            let k = p.len() as f64;
            (
                p.iter().map(|q| q.0).sum::<f64>() / k,
                p.iter().map(|q| q.1).sum::<f64>() / k,
            )
        };
        let means = [mean(&pts[0]), mean(&pts[1])];
        let (mut sxy, mut sxx) = (0.0, 0.0);
        for j in 0..2 {
            for &(x, y) in &pts[j] {
                sxy += (x - means[j].0) * (y - means[j].1);
                sxx += (x - means[j].0).powi(2);
            }
        }
        if sxx <= 0.0 {
            return Err(invalid(
                "fit_range",
                format!("[{z_lo}, {z_hi}] m"),
                "holds no spread of sinkage",
            ));
        }
        let n = sxy / sxx;
        let k: [f64; 2] = std::array::from_fn(|j| (means[j].1 - n * means[j].0).exp());
        let k_c = (k[0] - k[1]) / (1.0 / b1 - 1.0 / b2);
        let k_phi = k[0] - k_c / b1;
        let (mut r2, mut count) = (0.0, 0.0);
        for j in 0..2 {
            for &(x, y) in &pts[j] {
                r2 += (y - k[j].ln() - n * x).powi(2);
                count += 1.0;
            }
        }
        Ok(Self {
            k_c,
            k_phi,
            n,
            rms_log: (r2 / count).sqrt(),
        })
    }

    /// Bekker's (Wong's) static sinkage of a rigid wheel of diameter `diameter` (m) and
    /// width `width` (m) under `load` (N), m (module documentation; Wong, Theory of Ground
    /// Vehicles, eq. 2.64). NaN when `k_c + b k_phi <= 0` or `n >= 3` (the law then gives
    /// no positive sinkage).
    pub fn wheel_sinkage(&self, load: f64, diameter: f64, width: f64) -> f64 {
        let k = self.k_c + width * self.k_phi;
        if k <= 0.0 || self.n >= 3.0 {
            return f64::NAN;
        }
        (3.0 * load / ((3.0 - self.n) * k * diameter.sqrt())).powf(2.0 / (2.0 * self.n + 1.0))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn curve(k_c: f64, k_phi: f64, n: f64, b: f64) -> Vec<PlateSample> {
        (1..=20)
            .map(|i| {
                let z = 0.005 * i as f64;
                PlateSample {
                    sinkage: z,
                    pressure: (k_c / b + k_phi) * z.powf(n),
                }
            })
            .collect()
    }

    #[test]
    fn fit_recovers_bekker_parameters() {
        // Numbers of the order of a dry sand's (Wong, Theory of Ground Vehicles, table
        // 2.3; test numbers only): k_c 0.99 kN/m^(n+1), k_phi 1528.43 kN/m^(n+2), n 1.1.
        let (k_c, k_phi, n) = (0.99e3, 1528.43e3, 1.1);
        let (a, b) = (curve(k_c, k_phi, n, 0.05), curve(k_c, k_phi, n, 0.1));
        let f = Bekker::fit([(0.05, &a), (0.1, &b)], 0.0, 1.0).unwrap();
        assert!((f.n - n).abs() < 1e-12, "{f:?}");
        assert!((f.k_c / k_c - 1.0).abs() < 1e-9, "{f:?}");
        assert!((f.k_phi / k_phi - 1.0).abs() < 1e-12, "{f:?}");
        assert!(f.rms_log < 1e-12);
    }

    #[test]
    fn wheel_sinkage_satisfies_its_load_balance() {
        // Wong's derivation: W = b k sqrt(D) z0^((2n+1)/2) (3 - n) / 3 with k = k_c/b +
        // k_phi; the formula inverts it.
        let f = Bekker {
            k_c: 2e3,
            k_phi: 8e5,
            n: 0.9,
            rms_log: 0.0,
        };
        let (w, d, b) = (2000.0, 0.5, 0.2);
        let z = f.wheel_sinkage(w, d, b);
        let k = f.k_c / b + f.k_phi;
        let back = b * k * d.sqrt() * z.powf(0.5 * (2.0 * f.n + 1.0)) * (3.0 - f.n) / 3.0;
        assert!((back / w - 1.0).abs() < 1e-12, "{z} {back}");
        let bad = Bekker { k_phi: -1e9, ..f };
        assert!(bad.wheel_sinkage(w, d, b).is_nan());
    }

    #[test]
    fn bad_plate_input_names_the_field() {
        let spec = PlateSpec {
            soil: SoilSpec::default(),
            plate_width: 0.2,
            dx: 0.05,
            domain_width: 3.0,
            domain_depth: 2.0,
            final_sinkage: 0.05,
            speed: 0.1,
            ramp_time: 0.05,
        };
        let e = Plate::new(PlateSpec {
            plate_width: -0.2,
            ..spec
        })
        .unwrap_err();
        assert!(e.to_string().contains("plate.plate_width"), "{e}");
        let e = Plate::new(PlateSpec {
            final_sinkage: 1.0,
            ..spec
        })
        .unwrap_err();
        assert!(e.to_string().contains("plate.final_sinkage"), "{e}");
        let e = Bekker::fit([(0.1, &[]), (0.1, &[])], 0.0, 1.0).unwrap_err();
        assert!(e.to_string().contains("plate_widths"), "{e}");
    }
}
