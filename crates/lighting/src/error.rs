//! Validation errors of the lighting constructors.

use thiserror::Error;

/// Why a [`crate::Material`] or [`crate::Light`] was rejected. Each variant names the field.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum LightingError {
    /// A coefficient or intensity is below zero.
    #[error("{field}: must be non-negative, got {value}")]
    Negative {
        /// The offending field (`ka`, `intensity`, ...).
        field: &'static str,
        /// The offending value (one channel for colours).
        value: f32,
    },
    /// A value is NaN or infinite.
    #[error("{field}: must be finite, got {value}")]
    NonFinite {
        /// The offending field.
        field: &'static str,
        /// The offending value.
        value: f32,
    },
    /// A direction or edge vector has (almost) zero length and defines no direction.
    #[error("{field}: must be a non-zero vector")]
    ZeroVector {
        /// The offending field.
        field: &'static str,
    },
    /// A value lies outside its allowed range.
    #[error("{field}: must be in {range}, got {value}")]
    OutOfRange {
        /// The offending field.
        field: &'static str,
        /// The offending value.
        value: f32,
        /// The allowed range, in words.
        range: &'static str,
    },
    /// A value that another field rules out.
    #[error("{field}: {reason}, got {value}")]
    Conflict {
        /// The offending field.
        field: &'static str,
        /// The offending value (one channel for colours).
        value: f32,
        /// What the other field requires, in words.
        reason: &'static str,
    },
    /// A count (a number of samples) lies outside its allowed range; the value is kept as the
    /// whole number it was, so that the message echoes it exactly.
    #[error("{field}: must be in {range}, got {value}")]
    CountOutOfRange {
        /// The offending field.
        field: &'static str,
        /// The offending count.
        value: u32,
        /// The allowed range, in words.
        range: &'static str,
    },
    /// A name (from a scene file) is not one of the known ones.
    #[error("{field}: unknown name {name:?}, expected {expected}")]
    UnknownName {
        /// The offending field.
        field: &'static str,
        /// The name given.
        name: String,
        /// The accepted names, in words.
        expected: &'static str,
    },
}

/// Checks that `value` is finite and non-negative.
pub(crate) fn check_scalar(field: &'static str, value: f32) -> Result<(), LightingError> {
    if !value.is_finite() {
        return Err(LightingError::NonFinite { field, value });
    }
    if value < 0.0 {
        return Err(LightingError::Negative { field, value });
    }
    Ok(())
}

/// Checks a specular exponent: non-negative, finite or `+inf` (the perfect mirror).
pub(crate) fn check_shininess(value: f32) -> Result<(), LightingError> {
    let field = "shininess";
    if value.is_nan() {
        return Err(LightingError::OutOfRange {
            field,
            value,
            range: "[0, inf]",
        });
    }
    if value < 0.0 {
        return Err(LightingError::Negative { field, value });
    }
    Ok(())
}

/// Checks that every channel of `rgb` is finite and non-negative.
pub(crate) fn check_rgb(field: &'static str, rgb: glam::Vec3) -> Result<(), LightingError> {
    rgb.to_array()
        .into_iter()
        .try_for_each(|c| check_scalar(field, c))
}

/// Checks that `v` is finite (any sign).
pub(crate) fn check_finite_vec(field: &'static str, v: glam::Vec3) -> Result<(), LightingError> {
    match v.to_array().into_iter().find(|c| !c.is_finite()) {
        Some(value) => Err(LightingError::NonFinite { field, value }),
        None => Ok(()),
    }
}

/// Checks that `v` is finite and long enough to normalize.
pub(crate) fn check_direction(field: &'static str, v: glam::Vec3) -> Result<(), LightingError> {
    check_finite_vec(field, v)?;
    if v.length_squared() < phosphor_math::MIN_NORMALIZABLE_LENGTH_SQUARED {
        return Err(LightingError::ZeroVector { field });
    }
    Ok(())
}
