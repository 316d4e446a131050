//! Finite elements. One element type per file.
//!
//! - [`cable`]: the gradient-deficient ANCF cable/beam element (Gerstmayr & Shabana 2006).

pub mod cable;

pub use cable::{AncfCable, CableQuadrature, ElementMatrix, ElementVector};
