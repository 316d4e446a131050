//! # chrono-fea
//!
//! Finite elements (to be built; see the chrono-fea issue): ANCF cable/beam and shell
//! elements (pre-shaped, with internal pressure, for tires), linear tetrahedra; nodes are
//! variables of the descriptor, stepped implicitly with a sparse factorization (faer) as
//! the coupled mass operator, in contact through the ordinary contact rows.
