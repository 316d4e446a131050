//! (being built: see the chrono-vehicle issue)
