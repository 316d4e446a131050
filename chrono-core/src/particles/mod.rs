//! Particle infrastructure shared by the particle methods (DEM broad phase, SPH,
//! constraint fluids, MPM binning):
//!
//! - [`kernel`]: SPH smoothing kernels (cubic spline, Wendland C2) with gradients;
//! - [`grid`]: the uniform cell grid sorted by a counting sort, with neighbour
//!   iteration, CSR neighbour lists, unique pairs, periodic axes and the sorted
//!   permutation for reordering structure-of-arrays data;
//! - [`lattice`]: particle set-ups on the cubic lattice (fluid blocks, tanks with
//!   wall-marker layers, the dam-break and sloshing tanks), shared by the fluid models.

pub mod grid;
pub mod kernel;
pub mod lattice;

pub use grid::{CellGrid, GridConfig, NeighborList, PairScratch, Positions, permute};
pub use kernel::{Kernel, KernelKind};
