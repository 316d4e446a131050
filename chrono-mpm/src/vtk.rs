//! VTK (VTP) frames of MPM markers for ParaView.
//!
//! Per marker: velocity (m/s); Cauchy stress as pressure `p = -tr(sigma)/3` and von Mises
//! stress `sqrt(3/2) |dev sigma|` (Pa), with `sigma = tau / J` and `J = det F_E det F_P`;
//! the elastic and plastic volume ratios `J_E`, `J_P`; the plastic strain measure
//! `|ln sigma_i(F_P)|` (the norm of the Hencky strain of `F_P`); the mass (kg).

use std::path::Path;

use nalgebra::Vector3;
use rayon::prelude::*;

use crate::body::MpmBody;
use crate::error::Result;
use crate::material::SignedSvd;

/// The per-marker fields of a frame, in marker order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MarkerFields {
    /// Pressure `-tr(sigma)/3`, Pa.
    pub pressure: Vec<f64>,
    /// Von Mises stress, Pa.
    pub von_mises: Vec<f64>,
    /// `det F_E`.
    pub j_elastic: Vec<f64>,
    /// `det F_P`.
    pub j_plastic: Vec<f64>,
    /// Norm of the Hencky strain of `F_P`.
    pub plastic_strain: Vec<f64>,
}

impl MarkerFields {
    /// The fields of `body`'s markers.
    pub fn of(body: &MpmBody) -> Self {
        let mk = &body.markers;
        let mat = body.material();
        let rows: Vec<[f64; 5]> = (0..mk.len())
            .into_par_iter()
            .map(|p| {
                let (fe, fp) = (&mk.fe[p], &mk.fp[p]);
                let (je, jp) = (fe.determinant(), fp.determinant());
                let sigma = mat.kirchhoff(fe, fp) / (je * jp);
                let tr = sigma.trace();
                let dev = sigma - nalgebra::Matrix3::identity() * (tr / 3.0);
                let eps_p = SignedSvd::new(fp)
                    .map(|s| s.s.map(|x| x.abs().ln()).norm())
                    .unwrap_or(f64::NAN);
                [-tr / 3.0, (1.5f64).sqrt() * dev.norm(), je, jp, eps_p]
            })
            .collect();
        let col = |k: usize| rows.iter().map(|r| r[k]).collect();
        Self {
            pressure: col(0),
            von_mises: col(1),
            j_elastic: col(2),
            j_plastic: col(3),
            plastic_strain: col(4),
        }
    }
}

/// Writes `body`'s markers as a VTP file (vertex cells with the fields above).
pub fn write_markers_vtp(path: impl AsRef<Path>, body: &MpmBody) -> Result<()> {
    let f = MarkerFields::of(body);
    let mk = &body.markers;
    let points: Vec<Vector3<f64>> = mk.x.clone();
    chrono_core::io::vtk::write_points_vtp(
        path,
        &points,
        &[
            ("pressure", &f.pressure),
            ("von_mises", &f.von_mises),
            ("J_E", &f.j_elastic),
            ("J_P", &f.j_plastic),
            ("plastic_strain", &f.plastic_strain),
            ("mass", &mk.mass),
        ],
        &[("velocity", &mk.v)],
    )?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{FixedCorotated, GridSpec, MpmSettings};
    use nalgebra::Matrix3;

    #[test]
    fn fields_of_a_compressed_marker_and_a_written_frame() {
        let spec = GridSpec::new([0.0; 3], [4; 3], 0.1).unwrap();
        let mat = FixedCorotated::elastic(1e6, 0.25).unwrap();
        let mut body = MpmBody::new(spec, mat.into(), MpmSettings::default()).unwrap();
        body.markers
            .push(
                1.0,
                1e-3,
                Vector3::new(0.2, 0.2, 0.2),
                Vector3::new(0.0, 0.0, -1.0),
            )
            .unwrap();
        // Hydrostatic compression F_E = 0.99 I: sigma = lambda (J - 1) J / J 1 ... plus
        // 2 mu (F - R) F^T / J = 2 mu (0.99 - 1) 0.99 / J.
        let s = 0.99f64;
        body.markers.fe[0] = Matrix3::identity() * s;
        let f = MarkerFields::of(&body);
        let el = mat.elastic;
        let j = s.powi(3);
        let tau = 2.0 * el.mu * (s - 1.0) * s + el.lambda * (j - 1.0) * j;
        assert!((f.pressure[0] + tau / j).abs() < 1e-6 * tau.abs());
        assert!(f.von_mises[0].abs() < 1e-6 * tau.abs());
        assert!((f.j_elastic[0] - j).abs() < 1e-12);
        assert_eq!(f.j_plastic[0], 1.0);
        assert!(f.plastic_strain[0].abs() < 1e-12);
        let path = std::env::temp_dir().join(format!("chrono_mpm_vtk_{}.vtp", std::process::id()));
        write_markers_vtp(&path, &body).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        std::fs::remove_file(&path).ok();
        for name in [
            "pressure",
            "von_mises",
            "J_E",
            "J_P",
            "plastic_strain",
            "velocity",
        ] {
            assert!(text.contains(&format!("Name=\"{name}\"")), "{name} missing");
        }
    }
}
