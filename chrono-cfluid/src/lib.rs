//! # chrono-cfluid
//!
//! Constraint fluids (to be built; see the chrono-cfluid issue): fluid particles as 3-dof
//! variables and one density constraint per particle, `C_i = rho_i / rho_0 - 1`, as a
//! compliant bilateral row of the same CCP as the rigid bodies (H. Mazhar, PhD thesis,
//! UW-Madison 2016), with fluid–solid frictional contact as ordinary cone rows.
