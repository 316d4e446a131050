//! Constraint-fluid validation cases (chrono-cfluid): the incompressibility test of the
//! seed ("Incompressibility Test" table) and the dam break against Martin and Moyce (1952). See `docs/validation-cfluid.md`.

pub mod dam_break;
pub mod incompressibility;
