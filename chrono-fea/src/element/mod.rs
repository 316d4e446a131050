//! Finite elements. One element type per file.
//!
//! - [`cable`]: the gradient-deficient ANCF cable/beam element (Gerstmayr & Shabana 2006).
//! - [`tet`]: the linear 4-node tetrahedron, St. Venant–Kirchhoff or corotational linear.

pub mod cable;
pub mod tet;

pub use cable::{AncfCable, CableQuadrature, ElementMatrix, ElementVector};
pub use tet::{Tet4, TetMatrix, TetVector, polar, von_mises};
