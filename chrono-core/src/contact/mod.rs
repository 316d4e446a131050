//! Contact: turning collision points into constraint rows or forces.
//!
//! - NSC (complementarity): each contact point becomes a friction triplet of rows
//!   `(n, u, w)` in the Coulomb cone with the combined friction coefficient `mu`
//!   ([`nsc`]).
//! - SMC (penalty): each contact point gives a force from its overlap, its relative
//!   velocity and its tangential displacement history: Hooke or Hertz–Mindlin with damping
//!   mapped from the restitution, Coulomb cap, rolling and spinning resistance ([`smc`]).

pub mod nsc;
mod nsc_plain;
#[cfg(test)]
mod nsc_tests;
pub mod smc;
#[cfg(test)]
mod smc_tests;
mod sorted_map;
