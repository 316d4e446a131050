//! The error type of chrono-sph.

use chrono_core::ChronoError;
use thiserror::Error;

/// Errors from building or stepping an SPH system. Every variant names what was wrong:
/// the field and value for bad input, the particle (its stable id), step and time for a
/// diverging simulation.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum SphError {
    /// A setting or builder argument is out of range.
    #[error("invalid parameter `{field}` = {value}: {reason}")]
    InvalidParameter {
        /// The field, e.g. `settings.spacing`.
        field: String,
        /// The rejected value, as text.
        value: String,
        /// What a valid value is.
        reason: String,
    },
    /// A particle's state became NaN or infinite.
    #[error("non-finite {quantity} of particle {particle} at step {step} (t = {time} s)")]
    NonFinite {
        /// The particle id (its index at creation, stable across reordering).
        particle: u32,
        /// The step index.
        step: u64,
        /// Simulation time, s.
        time: f64,
        /// Which quantity (position, velocity, density, acceleration).
        quantity: &'static str,
    },
    /// The simulation diverged: a particle moves faster than the sound speed allows or
    /// the time step collapsed.
    #[error("diverged: particle {particle} at step {step} (t = {time} s): {what}")]
    Diverged {
        /// The particle id.
        particle: u32,
        /// The step index.
        step: u64,
        /// Simulation time, s.
        time: f64,
        /// The quantity and its value against the limit.
        what: String,
    },
    /// The Mach number exceeded the limit and the policy is
    /// [`MachPolicy::Error`](crate::MachPolicy::Error).
    #[error(
        "Mach number {mach:.3} > {limit} (particle {particle}, step {step}, t = {time} s): raise settings.sound_speed"
    )]
    MachExceeded {
        /// The particle id of the fastest particle.
        particle: u32,
        /// The step index.
        step: u64,
        /// Simulation time, s.
        time: f64,
        /// `|v| / c_s`.
        mach: f64,
        /// The limit.
        limit: f64,
    },
    /// Another rank of a distributed run failed or disagreed ([`crate::distributed`]):
    /// this rank stops instead of waiting for it.
    #[error("rank {rank}: {reason}")]
    Rank {
        /// The rank that failed.
        rank: usize,
        /// What happened there.
        reason: String,
    },
    /// An error from chrono-core (grid, kernel, i/o).
    #[error(transparent)]
    Core(ChronoError),
}

impl From<ChronoError> for SphError {
    /// A failed rank stays [`SphError::Rank`] (the transports live in chrono-core).
    fn from(e: ChronoError) -> Self {
        match e {
            ChronoError::Rank { rank, reason } => SphError::Rank { rank, reason },
            e => SphError::Core(e),
        }
    }
}

/// Result alias of chrono-sph.
pub type Result<T> = std::result::Result<T, SphError>;

impl SphError {
    /// Convenience constructor for [`SphError::InvalidParameter`].
    pub fn invalid(
        field: impl Into<String>,
        value: impl std::fmt::Display,
        reason: impl Into<String>,
    ) -> Self {
        SphError::InvalidParameter {
            field: field.into(),
            value: value.to_string(),
            reason: reason.into(),
        }
    }
}

/// Checks that `v` is finite and `> 0`.
pub(crate) fn positive(field: &str, v: f64) -> Result<f64> {
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(SphError::invalid(field, v, "must be finite and > 0"))
    }
}

/// Checks that `v` is finite and `>= 0`.
pub(crate) fn non_negative(field: &str, v: f64) -> Result<f64> {
    if v.is_finite() && v >= 0.0 {
        Ok(v)
    } else {
        Err(SphError::invalid(field, v, "must be finite and >= 0"))
    }
}

/// Checks that every component is finite.
pub(crate) fn finite3(field: &str, v: [f64; 3]) -> Result<()> {
    if v.iter().all(|c| c.is_finite()) {
        Ok(())
    } else {
        Err(SphError::invalid(
            field,
            format!("[{}, {}, {}]", v[0], v[1], v[2]),
            "must be finite",
        ))
    }
}
