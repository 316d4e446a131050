//! # chrono-sph
//!
//! Explicit weakly compressible SPH (to be built; see the chrono-sph issue): continuity for
//! density, the Tait equation of state `p = c_s^2 rho_0 / gamma ((rho/rho_0)^gamma - 1)`,
//! momentum with the symmetric pressure term and the Morris viscous term, XSPH, periodic
//! Shepard filtering (Monaghan 2005; Morris, Fox and Zhu 1997), wall marker boundaries,
//! and an adaptive time step (CFL, viscous and force criteria). Particles live in
//! structure-of-arrays storage and use chrono-core's cell grid and kernels.
