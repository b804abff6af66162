//! Values OpenSim 4 re-writes while it converts a document older than its own format, which it
//! then computes with: what a faithful reader of those documents must compute with too.

/// A number as OpenSim's conversion re-writes it, through a C++ stream at its default precision:
/// six significant digits (`%g`). A 3.x joint's `location_in_parent` of `-0.06772454` m moves
/// the joint by 4e-8 m to `-0.0677245` in OpenSim 4, and every length across it changes with it.
pub fn six_significant_digits(value: f64) -> f64 {
    if value == 0.0 || !value.is_finite() {
        return value;
    }
    format!("{value:.5e}").parse().unwrap_or(value)
}

/// [`six_significant_digits`] of each element.
pub fn six_significant_digits_each<const N: usize>(values: [f64; N]) -> [f64; N] {
    values.map(six_significant_digits)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The values OpenSim 4.6 wrote for subject01's (document 20302) `hip_r` offset frame when
    /// it converted `location_in_parent` -0.07243760 -0.06772454 0.08555218.
    #[test]
    fn rounds_as_a_cpp_stream_does() {
        assert_eq!(six_significant_digits_each([-0.07243760, -0.06772454, 0.08555218]), [-0.0724376, -0.0677245, 0.0855522]);
        assert_eq!(six_significant_digits(1234567.0), 1234570.0);
        assert_eq!(six_significant_digits(-2.5e-9), -2.5e-9);
        assert_eq!(six_significant_digits(0.0), 0.0);
    }
}
