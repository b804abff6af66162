//! Where an abscissa lies among a function's knots, decided exactly as OpenSim's
//! `SimmSpline`, `PiecewiseLinearFunction` and `PiecewiseConstantFunction` decide it.

/// Shortest knot interval used in coefficient formulas (SIMM's `TINY_NUMBER`): OpenSim
/// divides by `max(TINY_INTERVAL, x_{i+1} − x_i)`, so closer knots act as if 1e-7 apart.
pub(super) const TINY_INTERVAL: f64 = 1e-7;

/// Distance within which an abscissa counts as the first or last knot (SIMM's
/// `ROUNDOFF_ERROR`, `EQUAL_WITHIN_ERROR`).
const KNOT_TOLERANCE: f64 = 2e-13;

/// Position of an abscissa `x` relative to knots x_0 < … < x_{n−1}.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Segment {
    /// x < x_0: extrapolation from the first knot.
    Before,
    /// |x − x_0| ≤ 2e-13 (and not before it).
    AtFirst,
    /// x_k ≤ x ≤ x_{k+1} for the interval k found by OpenSim's bisection; at an interior
    /// knot either neighbouring interval may be returned, as in OpenSim.
    Interval(usize),
    /// |x − x_{n−1}| ≤ 2e-13 (and not after it).
    AtLast,
    /// x > x_{n−1}: extrapolation from the last knot.
    After,
}

/// Locates `x` among `knots` (strictly increasing, at least one). The tests run in OpenSim's
/// order: before, after, at the first knot, at the last knot, then bisection.
pub(super) fn locate(knots: &[f64], x: f64) -> Segment {
    let (first, last) = (knots[0], knots[knots.len() - 1]);
    if x < first {
        Segment::Before
    } else if x > last {
        Segment::After
    } else if (x - first).abs() <= KNOT_TOLERANCE {
        Segment::AtFirst
    } else if (x - last).abs() <= KNOT_TOLERANCE {
        Segment::AtLast
    } else {
        Segment::Interval(bisect(knots, x))
    }
}

/// OpenSim's bisection: halve [low, high) until x_k ≤ x ≤ x_{k+1} with k = ⌊(low + high)/2⌋.
/// Terminates (with some k < n) for any x, NaN included, without reading past the knots.
fn bisect(knots: &[f64], x: f64) -> usize {
    let (mut low, mut high) = (0, knots.len());
    loop {
        let k = (low + high) / 2;
        if x < knots[k] && k > low {
            high = k;
        } else if k + 1 < knots.len() && x > knots[k + 1] && k + 1 < high {
            low = k;
        } else {
            return k;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ends_within_tolerance_count_as_knots() {
        let knots = [0.0, 1.0, 2.0];
        assert_eq!(locate(&knots, -1e-13), Segment::Before);
        assert_eq!(locate(&knots, 1e-13), Segment::AtFirst);
        assert_eq!(locate(&knots, 2.0 - 1e-13), Segment::AtLast);
        assert_eq!(locate(&knots, 2.0 + 1e-13), Segment::After);
    }

    #[test]
    fn interior_knots_follow_the_bisection_path() {
        let knots = [0.0, 1.0, 2.0, 3.0, 4.0];
        // k = 2 first: x = 2 satisfies x_2 ≤ x ≤ x_3; x = 1 goes left to k = 1 (x_1 ≤ 1 ≤ x_2).
        assert_eq!(locate(&knots, 2.0), Segment::Interval(2));
        assert_eq!(locate(&knots, 1.0), Segment::Interval(1));
        assert_eq!(locate(&knots, 3.0), Segment::Interval(2));
        assert_eq!(locate(&knots, 3.5), Segment::Interval(3));
        assert_eq!(locate(&knots, 0.5), Segment::Interval(0));
    }

    #[test]
    fn nan_terminates() {
        assert_eq!(locate(&[0.0, 1.0, 2.0], f64::NAN), Segment::Interval(1));
        assert_eq!(locate(&[0.5], f64::NAN), Segment::Interval(0));
    }
}
