//! Input / output: CSV time series and VTK XML frames for ParaView.
//!
//! - [`csv`]: [`CsvWriter`] for a time series written row by row, [`write_csv`] one-shot.
//! - [`vtk`]: `.vtp` PolyData of rigid shapes ([`write_shapes_vtp`]) and of particles
//!   ([`write_points_vtp`]), and the `.pvd` collection ([`write_pvd`], in parts: [`write_pvd_parts`]) that lets ParaView
//!   play a series of frames.
//! - [`bodies`]: frames of every body's colliders, [`write_bodies_vtp`].
//! - [`grains`]: frames of grains (positions, radii, velocities), [`write_grains_vtp`].
//! - [`frames`]: [`FrameSeries`], a series of frames of any kind with its `.pvd`.
//!
//! Errors are [`ChronoError::Io`] naming the file.

pub mod bodies;
pub mod csv;
pub mod frames;
pub mod grains;
pub mod vtk;

pub use bodies::write_bodies_vtp;
pub use csv::{CsvWriter, write_csv};
pub use frames::{Every, FrameSeries};
pub use grains::write_grains_vtp;
pub use vtk::{
    ShapeMeshOptions, write_points_vtp, write_pvd, write_pvd_parts, write_shapes_vtp,
    write_shapes_vtp_with,
};

use std::path::Path;

use crate::error::ChronoError;

/// A [`ChronoError::Io`] for `path`.
pub(crate) fn io_error(path: &Path, err: impl std::fmt::Display) -> ChronoError {
    ChronoError::Io {
        path: path.display().to_string(),
        message: err.to_string(),
    }
}

/// Format a float for text output: shortest representation that parses back to the same
/// `f64`; scientific notation for very small or very large magnitudes.
pub(crate) fn fmt_f64(x: f64, out: &mut String) {
    use std::fmt::Write;
    let a = x.abs();
    if x == 0.0 || (1e-5..1e15).contains(&a) || !x.is_finite() {
        let _ = write!(out, "{x}");
    } else {
        let _ = write!(out, "{x:e}");
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn floats_round_trip() {
        for x in [
            0.0,
            -0.0,
            1.0,
            0.1,
            -1.0 / 3.0,
            1e-300,
            6.02e23,
            123456.789,
            f64::MAX,
            f64::MIN_POSITIVE,
            1e-5,
            1e15,
        ] {
            let mut s = String::new();
            super::fmt_f64(x, &mut s);
            assert_eq!(s.parse::<f64>().unwrap().to_bits(), x.to_bits(), "{s}");
            assert!(s.len() < 26, "{s}");
        }
    }
}
