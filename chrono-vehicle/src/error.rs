//! The error type of chrono-vehicle.

use thiserror::Error;

/// Errors from building or running a vehicle. Every variant names what was wrong.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum VehicleError {
    /// A parameter of a template, tire, driver or terrain is out of its valid range.
    #[error("invalid parameter `{field}` = {value}: {reason}")]
    InvalidParameter {
        /// The field, e.g. `suspension.front.spring.rest_length`.
        field: String,
        /// The rejected value, as text.
        value: String,
        /// What a valid value is.
        reason: String,
    },
    /// A vehicle or subsystem description could not be read.
    #[error("cannot read vehicle data {path}: {message}")]
    Data {
        /// The file (or `<string>`).
        path: String,
        /// What the parser said.
        message: String,
    },
    /// An error of the multibody system (a bad body, a diverging step ...).
    #[error(transparent)]
    Core(#[from] chrono_core::ChronoError),
    /// An error of a finite-element part (the ANCF tire's mesh, inflation or mount).
    #[error(transparent)]
    Fea(#[from] chrono_fea::FeaError),
}

/// Result alias of chrono-vehicle.
pub type Result<T> = std::result::Result<T, VehicleError>;

impl VehicleError {
    /// Convenience constructor for [`VehicleError::InvalidParameter`].
    pub fn invalid(
        field: impl Into<String>,
        value: impl std::fmt::Display,
        reason: impl Into<String>,
    ) -> Self {
        Self::InvalidParameter {
            field: field.into(),
            value: value.to_string(),
            reason: reason.into(),
        }
    }
}

/// `value` if it is finite and > 0, else an error naming `field`.
pub fn check_positive(field: &str, value: f64) -> Result<f64> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(VehicleError::invalid(
            field,
            value,
            "must be finite and > 0",
        ))
    }
}

/// `value` if it is finite and >= 0, else an error naming `field`.
pub fn check_non_negative(field: &str, value: f64) -> Result<f64> {
    if value.is_finite() && value >= 0.0 {
        Ok(value)
    } else {
        Err(VehicleError::invalid(
            field,
            value,
            "must be finite and >= 0",
        ))
    }
}

/// `value` if it is finite, else an error naming `field`.
pub fn check_finite(field: &str, value: f64) -> Result<f64> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(VehicleError::invalid(field, value, "must be finite"))
    }
}
