//! Finite elements. One element type per file.
//!
//! - [`cable`]: the gradient-deficient ANCF cable/beam element (Gerstmayr & Shabana 2006).
//! - [`beam`]: the fully parameterized 3D ANCF beam (structural-mechanics strains,
//!   selective reduced integration, curved reference, torsion).
//! - [`tet`]: the linear 4-node tetrahedron, St. Venant–Kirchhoff or corotational linear.
//! - [`shell`]: the ANCF 4-node shell with ANS and EAS (Yamashita et al. 2015).

pub mod beam;
pub mod cable;
pub mod shell;
pub mod tet;

pub use beam::{AncfBeam, BeamMatrix, BeamQuadrature, BeamVector};
pub use cable::{AncfCable, CableQuadrature, ElementMatrix, ElementVector};
pub use shell::{AncfShell, ShellLocking, ShellMaterial, ShellMatrix, ShellVector};
pub use tet::{Tet4, TetMatrix, TetVector, polar, von_mises};
