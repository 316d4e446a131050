//! # chrono-mpm
//!
//! The material point method (to be built): cubic B-spline transfers between markers and a
//! background grid, elasto-plastic models (snow-like hardening, sand), and the split of the
//! stress into pressure, solved by constraint fluids, and shear, solved by MPM (Chorin
//! split; Stomakhin et al., "Augmented MPM for phase-change and varied materials", ACM TOG 2014).
