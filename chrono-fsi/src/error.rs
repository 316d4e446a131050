//! The error type of chrono-fsi: every variant names the body or field and the value.

use thiserror::Error;

/// Errors from building or stepping a coupled fluid–solid scene.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum FsiError {
    /// A parameter is out of its valid range (or not finite).
    #[error("invalid parameter `{field}` = {value}: {reason}")]
    InvalidParameter {
        /// The field.
        field: String,
        /// Its value, formatted.
        value: String,
        /// The valid range.
        reason: String,
    },
    /// A body's shape has no marker generation.
    #[error("body \"{body}\": no BCE marker generation for a {shape} (box, sphere, cylinder only)")]
    UnsupportedShape {
        /// The body's name.
        body: String,
        /// The shape kind.
        shape: String,
    },
    /// A body thinner than the kernel support: the fluid on both sides would interact
    /// through it.
    #[error(
        "body \"{body}\": its {shape} is {thickness} m thick, thinner than the kernel support 2 h = {support} m (refine the spacing)"
    )]
    BodyThinnerThanSupport {
        /// The body's name.
        body: String,
        /// The shape kind.
        shape: String,
        /// Its smallest dimension, m.
        thickness: f64,
        /// The kernel support, m.
        support: f64,
    },
    /// The fluid spacing does not resolve a body.
    #[error(
        "body \"{body}\": the spacing {spacing} m does not resolve its {shape} ({thickness} m thick: at least {min_cells} spacings needed)"
    )]
    Unresolved {
        /// The body's name.
        body: String,
        /// The shape kind.
        shape: String,
        /// Its smallest dimension, m.
        thickness: f64,
        /// The fluid spacing, m.
        spacing: f64,
        /// The required number of spacings across.
        min_cells: f64,
    },
    /// A body carries no collider to make markers from.
    #[error("body \"{body}\" has no collider shape to generate BCE markers from")]
    NoShape {
        /// The body's name.
        body: String,
    },
    /// An error of the fluid (chrono-sph).
    #[error(transparent)]
    Sph(#[from] chrono_sph::SphError),
    /// An error of the multibody system (chrono-core).
    #[error(transparent)]
    Core(#[from] chrono_core::ChronoError),
}

impl FsiError {
    /// An [`FsiError::InvalidParameter`].
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

/// `Ok` if `value` is finite and positive, else an [`FsiError::InvalidParameter`] naming
/// `field` (the scenes' parameter checks).
pub(crate) fn check_positive(field: &str, value: f64) -> Result<()> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(FsiError::invalid(field, value, "must be finite and > 0"))
    }
}

/// Result alias of chrono-fsi.
pub type Result<T> = std::result::Result<T, FsiError>;
