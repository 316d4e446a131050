//! Contact: turning collision points into constraint rows.
//!
//! NSC (complementarity): each contact point becomes a friction triplet of rows
//! `(n, u, w)` in the Coulomb cone with the combined friction coefficient `mu`
//! ([`nsc`]). SMC (penalty, Hertz–Mindlin) comes with the granular issue.

pub mod nsc;
