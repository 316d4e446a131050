//! The CCP solver wrapper that measures the solve's share of a step (chrono-ccp's, used by
//! the cases' speed figures).

pub(crate) use chrono_ccp::TimedSolver;
