//! Why an SQP solver could not be built or started. Non-convergence is not an error but an
//! [`NlpStatus`](super::NlpStatus).

/// Inconsistent problem data or settings.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum NlpError {
    /// A vector has the wrong length.
    #[error("{what} has {found} entries, expected {expected}")]
    Dimension { what: &'static str, expected: usize, found: usize },
    /// A bound pair with lower > upper, lower = +∞, upper = −∞ or a NaN.
    #[error("{what} {index}: the range [{lower}, {upper}] is empty or not a number")]
    Range { what: &'static str, index: usize, lower: f64, upper: f64 },
    /// A start point entry that is not finite.
    #[error("start point entry {index} is {value}")]
    StartPoint { index: usize, value: f64 },
    /// A setting out of range.
    #[error("setting {name} is out of range")]
    Setting { name: &'static str },
}
