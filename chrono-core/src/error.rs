//! The error type of chrono-core.

use thiserror::Error;

/// Errors from building or stepping a system. Every variant names what was wrong.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum ChronoError {
    /// A parameter is out of its valid range (or not finite).
    #[error("invalid parameter `{field}` = {value}: {reason}")]
    InvalidParameter {
        /// The field or argument, e.g. `body.mass`.
        field: String,
        /// The rejected value, as text.
        value: String,
        /// What a valid value is.
        reason: String,
    },
    /// A handle (body, collider, joint, item) that does not exist in this system.
    #[error("unknown {kind} handle {index} in `{field}`")]
    UnknownHandle {
        /// `body`, `joint`, `collider` ...
        kind: &'static str,
        /// The index of the handle.
        index: usize,
        /// The field that named it.
        field: String,
    },
    /// A body handle that names no body of this system: the body was removed (or the
    /// handle comes from another system).
    #[error("stale or unknown handle {handle}")]
    StaleBody {
        /// The handle.
        handle: crate::body::BodyHandle,
    },
    /// An item handle that names no item of this system (removed, or from another system).
    #[error("stale or unknown handle {handle}")]
    StaleItem {
        /// The handle.
        handle: crate::item::ItemHandle,
    },
    /// A joint handle that names no joint of this system (removed, or from another system).
    #[error("stale or unknown handle {handle}")]
    StaleJoint {
        /// The handle.
        handle: crate::joint::JointHandle,
    },
    /// A force element handle that names no force element of this system (removed, or
    /// from another system).
    #[error("stale or unknown handle {handle}")]
    StaleForce {
        /// The handle.
        handle: crate::force::ForceHandle,
    },
    /// A body cannot be removed while joints or force elements refer to it (remove those
    /// first).
    #[error("{handle} (\"{name}\") is still used by {users:?}")]
    BodyInUse {
        /// The body.
        handle: crate::body::BodyHandle,
        /// Its name.
        name: String,
        /// The joints and force elements that refer to it, e.g. `joint 0v0 ("link")`.
        users: Vec<String>,
    },
    /// The state became non-finite (NaN or infinity) during a step.
    #[error("non-finite state in {item} at step {step} (t = {time} s): {what}")]
    NonFinite {
        /// The body or item, e.g. `body 3 ("box")`.
        item: String,
        /// The step index at which it was detected.
        step: u64,
        /// Simulation time at the start of that step, s.
        time: f64,
        /// Which quantity (position, velocity, impulse ...).
        what: String,
    },
    /// The state left its plausible range (a diverging simulation), though still finite.
    #[error("diverged: {item} at step {step} (t = {time} s): {what}")]
    Diverged {
        /// The body or item.
        item: String,
        /// The step index at which it was detected.
        step: u64,
        /// Simulation time at the start of that step, s.
        time: f64,
        /// Which quantity and its value against the limit.
        what: String,
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
    /// The collision library could not handle a pair of shapes.
    #[error("collision between {a} and {b} is not supported: {reason}")]
    Collision {
        /// The first collider.
        a: String,
        /// The second collider.
        b: String,
        /// Why.
        reason: String,
    },
    /// A physics item asks for something the chosen stepper does not do (e.g. collision
    /// proxies in an SMC system): refused instead of silently ignored.
    #[error("item \"{item}\" is not supported by {stepper}: {reason}")]
    ItemNotSupported {
        /// The item's name.
        item: String,
        /// The stepper, e.g. `the SMC step`.
        stepper: String,
        /// What it asked for.
        reason: String,
    },
    /// Reading or writing a file failed.
    #[error("i/o error on {path}: {message}")]
    Io {
        /// The file.
        path: String,
        /// The underlying error.
        message: String,
    },
    /// An error of a domain crate (chrono-fea, ...) raised inside a step or an item: the
    /// cause is kept as the [`source`](std::error::Error::source), and the message
    /// repeats it, so both name the real field.
    #[error("{domain}: {source}")]
    Domain {
        /// The crate that raised it, e.g. `chrono-fea`.
        domain: String,
        /// The cause.
        #[source]
        source: DomainError,
    },
}

/// The cause of a [`ChronoError::Domain`]: any error, shared (so the error stays
/// `Clone`); equal when it is the same error or has the same message.
#[derive(Debug, Clone)]
pub struct DomainError(pub std::sync::Arc<dyn std::error::Error + Send + Sync>);

impl std::fmt::Display for DomainError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        self.0.fmt(f)
    }
}

impl std::error::Error for DomainError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        self.0.source()
    }
}

impl PartialEq for DomainError {
    fn eq(&self, other: &Self) -> bool {
        std::sync::Arc::ptr_eq(&self.0, &other.0) || self.0.to_string() == other.0.to_string()
    }
}

/// Result alias of chrono-core.
pub type Result<T> = std::result::Result<T, ChronoError>;

impl ChronoError {
    /// Convenience constructor for [`ChronoError::InvalidParameter`].
    pub fn invalid(
        field: impl Into<String>,
        value: impl std::fmt::Display,
        reason: impl Into<String>,
    ) -> Self {
        ChronoError::InvalidParameter {
            field: field.into(),
            value: value.to_string(),
            reason: reason.into(),
        }
    }

    /// A [`ChronoError::Domain`]: `source`, an error of the crate `domain`, kept as the
    /// cause.
    pub fn domain(
        domain: impl Into<String>,
        source: impl std::error::Error + Send + Sync + 'static,
    ) -> Self {
        ChronoError::Domain {
            domain: domain.into(),
            source: DomainError(std::sync::Arc::new(source)),
        }
    }
}

/// Check that `value` is finite; `field` names it in the error.
pub fn check_finite(field: &str, value: f64) -> Result<f64> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(ChronoError::invalid(field, value, "must be finite"))
    }
}

/// Check that `value` is finite and strictly positive.
pub fn check_positive(field: &str, value: f64) -> Result<f64> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(ChronoError::invalid(field, value, "must be finite and > 0"))
    }
}

/// Check that `value` is finite and >= 0.
pub fn check_non_negative(field: &str, value: f64) -> Result<f64> {
    if value.is_finite() && value >= 0.0 {
        Ok(value)
    } else {
        Err(ChronoError::invalid(
            field,
            value,
            "must be finite and >= 0",
        ))
    }
}

/// Check that every component of a vector is finite.
pub fn check_finite3(field: &str, v: &nalgebra::Vector3<f64>) -> Result<()> {
    if crate::math::is_finite3(v) {
        Ok(())
    } else {
        Err(ChronoError::invalid(
            field,
            format!("[{}, {}, {}]", v.x, v.y, v.z),
            "must be finite",
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn errors_name_the_field_and_value() {
        let e = check_positive("body.mass", -1.0).unwrap_err();
        let s = e.to_string();
        assert!(s.contains("body.mass") && s.contains("-1"), "{s}");
        assert!(
            check_finite("h", f64::NAN)
                .unwrap_err()
                .to_string()
                .contains("NaN")
        );
        assert!(check_non_negative("mu", 0.0).is_ok());
    }
}
