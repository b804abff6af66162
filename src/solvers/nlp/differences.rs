//! Central finite differences of f and c, kept inside the bounds.
//!
//! Variable j is stepped by h_j = ε^{1/3}·max(1, |x_j|) (ε the machine epsilon, so h ≈ 6·10⁻⁶
//! relative: truncation and rounding errors balance at ~ε^{2/3} ≈ 4·10⁻¹¹ relative) to
//! x_j ± h_j, each clipped to [x_l, x_u]; the derivative is the divided difference between the
//! two points. Where one of them cannot be evaluated, or lies on x itself, the difference is
//! one-sided from x. A fixed variable (x_l = x_u) gets a zero column.

use nalgebra::DMatrix;

use super::problem::{EvaluationError, NlpProblem};

/// ∇f and ∂c/∂x at `x` by central differences of `problem.evaluate` (2n evaluations, plus one
/// at x where a one-sided difference is needed).
pub fn central_differences<P: NlpProblem + ?Sized>(
    problem: &mut P,
    x: &[f64],
    gradient: &mut [f64],
    jacobian: &mut DMatrix<f64>,
) -> Result<(), EvaluationError> {
    let (lower, upper) = problem.bounds();
    let m = jacobian.nrows();
    let mut point = x.to_vec();
    let mut base: Option<(f64, Vec<f64>)> = None;
    let (mut plus, mut minus) = (vec![0.0; m], vec![0.0; m]);
    for j in 0..x.len() {
        let h = f64::EPSILON.cbrt() * x[j].abs().max(1.0);
        let (high, low) = ((x[j] + h).min(upper[j]), (x[j] - h).max(lower[j]));
        if high <= low {
            gradient[j] = 0.0;
            jacobian.column_mut(j).fill(0.0);
            continue;
        }
        let f_plus = side(problem, &mut point, j, high, &mut plus);
        let f_minus = side(problem, &mut point, j, low, &mut minus);
        if (f_plus.is_none() || f_minus.is_none()) && base.is_none() {
            let mut constraints = vec![0.0; m];
            let f = finite_evaluation(problem, x, &mut constraints).ok_or_else(|| EvaluationError::new("the point of the differences failed"))?;
            base = Some((f, constraints));
        }
        let at_x = base.as_ref().map(|(f, c)| (x[j], *f, c));
        let (high, f_high, c_high) = f_plus.map(|f| (high, f, &plus)).or(at_x).expect("evaluated above");
        let (low, f_low, c_low) = f_minus.map(|f| (low, f, &minus)).or(at_x).expect("evaluated above");
        if high <= low {
            return Err(EvaluationError::new(format!("neither difference of variable {j} could be evaluated")));
        }
        let width = high - low;
        gradient[j] = (f_high - f_low) / width;
        for i in 0..m {
            jacobian[(i, j)] = (c_high[i] - c_low[i]) / width;
        }
    }
    Ok(())
}

/// f and c at x with x_j = value (into `constraints`); `None` when x_j = value is x itself or
/// the evaluation failed or was not finite.
fn side<P: NlpProblem + ?Sized>(problem: &mut P, point: &mut [f64], j: usize, value: f64, constraints: &mut [f64]) -> Option<f64> {
    let original = point[j];
    point[j] = value;
    let result = if value == original { None } else { finite_evaluation(problem, point, constraints) };
    point[j] = original;
    result
}

/// f (and c) when the evaluation succeeds with finite values.
pub(super) fn finite_evaluation<P: NlpProblem + ?Sized>(problem: &mut P, x: &[f64], constraints: &mut [f64]) -> Option<f64> {
    let f = problem.evaluate(x, constraints).ok()?;
    (f.is_finite() && constraints.iter().all(|c| c.is_finite())).then_some(f)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// f = x₀² x₁ + eˣ¹, c = (sin x₀, x₀ x₁), evaluation fails for x₀ > 1.
    struct Smooth {
        lower: Vec<f64>,
        upper: Vec<f64>,
    }

    impl NlpProblem for Smooth {
        fn dimension(&self) -> usize {
            2
        }

        fn bounds(&self) -> (Vec<f64>, Vec<f64>) {
            (self.lower.clone(), self.upper.clone())
        }

        fn constraint_bounds(&self) -> (Vec<f64>, Vec<f64>) {
            (vec![0.0; 2], vec![0.0; 2])
        }

        fn evaluate(&mut self, x: &[f64], c: &mut [f64]) -> Result<f64, EvaluationError> {
            if x[0] > 1.0 {
                return Err(EvaluationError::new("outside"));
            }
            c[0] = x[0].sin();
            c[1] = x[0] * x[1];
            Ok(x[0] * x[0] * x[1] + x[1].exp())
        }
    }

    fn differences(problem: &mut Smooth, x: &[f64]) -> (Vec<f64>, DMatrix<f64>) {
        let mut gradient = vec![0.0; 2];
        let mut jacobian = DMatrix::zeros(2, 2);
        central_differences(problem, x, &mut gradient, &mut jacobian).unwrap();
        (gradient, jacobian)
    }

    fn exact(x: &[f64]) -> (Vec<f64>, DMatrix<f64>) {
        let gradient = vec![2.0 * x[0] * x[1], x[0] * x[0] + x[1].exp()];
        (gradient, DMatrix::from_row_slice(2, 2, &[x[0].cos(), 0.0, x[1], x[0]]))
    }

    #[test]
    fn central_differences_are_accurate_inside_the_bounds() {
        let mut problem = Smooth { lower: vec![f64::NEG_INFINITY; 2], upper: vec![f64::INFINITY; 2] };
        let x = [0.3, -0.7];
        let ((g, j), (g_exact, j_exact)) = (differences(&mut problem, &x), exact(&x));
        assert!(g.iter().zip(&g_exact).all(|(a, b)| (a - b).abs() < 1e-9));
        assert!((j - j_exact).amax() < 1e-9);
    }

    #[test]
    fn differences_at_a_bound_or_a_failing_side_are_one_sided() {
        // x₀ at its upper bound 0.5 and x₁ at its lower bound: forward and backward differences.
        let mut problem = Smooth { lower: vec![-1.0, -0.7], upper: vec![0.5, 2.0] };
        let x = [0.5, -0.7];
        let ((g, j), (g_exact, j_exact)) = (differences(&mut problem, &x), exact(&x));
        assert!(g.iter().zip(&g_exact).all(|(a, b)| (a - b).abs() < 1e-4));
        assert!((j - j_exact).amax() < 1e-4);
        // x₀ = 1: the evaluation beyond it fails, the backward difference is used.
        let mut problem = Smooth { lower: vec![f64::NEG_INFINITY; 2], upper: vec![f64::INFINITY; 2] };
        let x = [1.0, 0.2];
        let ((g, _), (g_exact, _)) = (differences(&mut problem, &x), exact(&x));
        assert!((g[0] - g_exact[0]).abs() < 1e-4);
    }

    #[test]
    fn a_fixed_variable_has_a_zero_column() {
        let mut problem = Smooth { lower: vec![0.2, f64::NEG_INFINITY], upper: vec![0.2, f64::INFINITY] };
        let (g, j) = differences(&mut problem, &[0.2, 0.1]);
        assert_eq!(g[0], 0.0);
        assert_eq!(j.column(0).amax(), 0.0);
    }
}
