//! The validated bounds of a problem and the constraint violation they define.

use super::error::NlpError;
use super::problem::NlpProblem;

/// x_l ≤ x ≤ x_u and c_l ≤ c ≤ c_u.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Limits {
    pub lower: Vec<f64>,
    pub upper: Vec<f64>,
    pub c_lower: Vec<f64>,
    pub c_upper: Vec<f64>,
}

impl Limits {
    /// The problem's bounds, checked for length and non-empty ranges.
    pub fn of<P: NlpProblem + ?Sized>(problem: &P) -> Result<Limits, NlpError> {
        let n = problem.dimension();
        let (lower, upper) = problem.bounds();
        let (c_lower, c_upper) = problem.constraint_bounds();
        length("the lower bounds", n, lower.len())?;
        length("the upper bounds", n, upper.len())?;
        length("the constraints' upper bounds", c_lower.len(), c_upper.len())?;
        ranges("variable", &lower, &upper)?;
        ranges("constraint", &c_lower, &c_upper)?;
        Ok(Limits { lower, upper, c_lower, c_upper })
    }

    pub fn variables(&self) -> usize {
        self.lower.len()
    }

    pub fn constraints(&self) -> usize {
        self.c_lower.len()
    }

    /// x moved into the bounds.
    pub fn project(&self, x: &mut [f64]) {
        for ((x, l), u) in x.iter_mut().zip(&self.lower).zip(&self.upper) {
            *x = x.clamp(*l, *u);
        }
    }

    /// dist(cᵢ, [c_l,i, c_u,i]).
    pub fn row_violation(&self, i: usize, c: f64) -> f64 {
        (self.c_lower[i] - c).max(c - self.c_upper[i]).max(0.0)
    }

    /// V = Σᵢ dist(cᵢ, [c_l,i, c_u,i]), the ℓ1 violation of the merit function.
    pub fn l1_violation(&self, c: impl IntoIterator<Item = f64>) -> f64 {
        c.into_iter().enumerate().map(|(i, c)| self.row_violation(i, c)).sum()
    }

    /// maxᵢ dist(cᵢ, [c_l,i, c_u,i]), the reported violation.
    pub fn max_violation(&self, c: &[f64]) -> f64 {
        c.iter().enumerate().map(|(i, &c)| self.row_violation(i, c)).fold(0.0, f64::max)
    }
}

fn length(what: &'static str, expected: usize, found: usize) -> Result<(), NlpError> {
    if expected == found {
        Ok(())
    } else {
        Err(NlpError::Dimension { what, expected, found })
    }
}

fn ranges(what: &'static str, lower: &[f64], upper: &[f64]) -> Result<(), NlpError> {
    for (index, (&l, &u)) in lower.iter().zip(upper).enumerate() {
        if l.is_nan() || u.is_nan() || l > u || l == f64::INFINITY || u == f64::NEG_INFINITY {
            return Err(NlpError::Range { what, index, lower: l, upper: u });
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn violations_are_distances_from_the_ranges() {
        let limits = Limits { lower: vec![], upper: vec![], c_lower: vec![0.0, f64::NEG_INFINITY, 1.0], c_upper: vec![0.0, 2.0, f64::INFINITY] };
        let c = [-0.5, 3.0, 1.5];
        assert_eq!(limits.l1_violation(c), 1.5);
        assert_eq!(limits.max_violation(&c), 1.0);
    }
}
