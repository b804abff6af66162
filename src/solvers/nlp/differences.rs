//! Finite differences of f and c, kept inside the bounds.
//!
//! Variable j is stepped by h_j = ε^{1/3}·max(1, |x_j|) (ε the machine epsilon, so h ≈ 6·10⁻⁶
//! relative: truncation and rounding errors of the second-order formulas balance at
//! ~ε^{2/3} ≈ 4·10⁻¹¹ relative):
//! - central, (F(x + h) − F(x − h)) / 2h, with h shortened to the room left by the bounds when
//!   that is at least h_j/4;
//! - otherwise (x at or near a bound), or where a central point cannot be evaluated,
//!   one-sided of second order, (−3F(x) + 4F(x + s) − F(x + 2s)) / 2s with s = ±min(h, room/2)
//!   towards the side with more room (first order, (F(x + s) − F(x)) / s, when x + 2s fails);
//! - a fixed variable (x_l = x_u) gets a zero column.
//!
//! Only points inside the bounds are evaluated.

use nalgebra::DMatrix;

use super::problem::{EvaluationError, NlpProblem};

/// A step counts as central when the bounds leave at least this fraction of h on both sides.
const CENTRAL_ROOM: f64 = 0.25;

/// ∇f and ∂c/∂x at `x` by finite differences of `problem.evaluate`: 2n evaluations, plus one at
/// x and a few more where variables sit at bounds or evaluations fail.
pub fn central_differences<P: NlpProblem + ?Sized>(
    problem: &mut P,
    x: &[f64],
    gradient: &mut [f64],
    jacobian: &mut DMatrix<f64>,
) -> Result<(), EvaluationError> {
    let (lower, upper) = problem.bounds();
    let mut stencil = Stencil::new(problem, x, jacobian.nrows());
    for j in 0..x.len() {
        let h = f64::EPSILON.cbrt() * x[j].abs().max(1.0);
        let (room_up, room_down) = (upper[j] - x[j], x[j] - lower[j]);
        let column = if room_up <= 0.0 && room_down <= 0.0 {
            Some(Column::Zero)
        } else {
            let central = h.min(room_up).min(room_down);
            let directions = if room_up >= room_down { [(1.0, room_up), (-1.0, room_down)] } else { [(-1.0, room_down), (1.0, room_up)] };
            (central >= CENTRAL_ROOM * h).then(|| stencil.central(j, central)).flatten().or_else(|| {
                directions.into_iter().filter(|(_, room)| *room > 0.0).find_map(|(sign, room)| stencil.one_sided(j, sign * h.min(0.5 * room)))
            })
        };
        match column {
            Some(column) => stencil.write(column, j, gradient, jacobian),
            None => return Err(EvaluationError::new(format!("no difference of variable {j} could be evaluated"))),
        }
    }
    Ok(())
}

/// Which formula a column takes (its points are in the stencil's buffers).
#[derive(Debug, Clone, Copy)]
enum Column {
    Zero,
    /// (F₁ − F₂) / 2h with F₁ = F(x + h), F₂ = F(x − h).
    Central(f64),
    /// (−3F(x) + 4F₁ − F₂) / 2s with F₁ = F(x + s), F₂ = F(x + 2s).
    SecondOrder(f64),
    /// (F₁ − F(x)) / s.
    FirstOrder(f64),
}

/// Evaluations around x: F = (f, c) at two points and, once needed, at x itself.
struct Stencil<'a, P: NlpProblem + ?Sized> {
    problem: &'a mut P,
    x: &'a [f64],
    point: Vec<f64>,
    first: (f64, Vec<f64>),
    second: (f64, Vec<f64>),
    base: Option<(f64, Vec<f64>)>,
}

impl<'a, P: NlpProblem + ?Sized> Stencil<'a, P> {
    fn new(problem: &'a mut P, x: &'a [f64], m: usize) -> Self {
        Stencil { problem, x, point: x.to_vec(), first: (0.0, vec![0.0; m]), second: (0.0, vec![0.0; m]), base: None }
    }

    /// F at x with x_j moved by `offset`, into the first or second buffer.
    fn evaluate(&mut self, j: usize, offset: f64, second: bool) -> bool {
        self.point[j] = self.x[j] + offset;
        let target = if second { &mut self.second } else { &mut self.first };
        let result = finite_evaluation(self.problem, &self.point, &mut target.1);
        self.point[j] = self.x[j];
        result.map(|f| target.0 = f).is_some()
    }

    fn central(&mut self, j: usize, h: f64) -> Option<Column> {
        (self.evaluate(j, h, false) && self.evaluate(j, -h, true)).then_some(Column::Central(h))
    }

    fn one_sided(&mut self, j: usize, s: f64) -> Option<Column> {
        if self.base.is_none() {
            let mut constraints = vec![0.0; self.first.1.len()];
            let f = finite_evaluation(self.problem, self.x, &mut constraints)?;
            self.base = Some((f, constraints));
        }
        if !self.evaluate(j, s, false) {
            return None;
        }
        Some(if self.evaluate(j, 2.0 * s, true) { Column::SecondOrder(s) } else { Column::FirstOrder(s) })
    }

    /// Column j of the gradient (f) and Jacobian (c) by `column`'s formula.
    fn write(&self, column: Column, j: usize, gradient: &mut [f64], jacobian: &mut DMatrix<f64>) {
        let zero = (0.0, Vec::new());
        let base = self.base.as_ref().unwrap_or(&zero);
        let (weights, denominator) = match column {
            Column::Zero => ([0.0; 3], 1.0),
            Column::Central(h) => ([0.0, 1.0, -1.0], 2.0 * h),
            Column::SecondOrder(s) => ([-3.0, 4.0, -1.0], 2.0 * s),
            Column::FirstOrder(s) => ([-1.0, 1.0, 0.0], s),
        };
        let combine = |b: f64, f1: f64, f2: f64| {
            let [w0, w1, w2] = weights;
            let mut sum = w1 * f1 + w2 * f2;
            if w0 != 0.0 {
                sum += w0 * b;
            }
            sum / denominator
        };
        gradient[j] = combine(base.0, self.first.0, self.second.0);
        for i in 0..jacobian.nrows() {
            let b = base.1.get(i).copied().unwrap_or(0.0);
            jacobian[(i, j)] = combine(b, self.first.1[i], self.second.1[i]);
        }
    }
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
    fn differences_at_a_bound_or_a_failing_side_are_one_sided_of_second_order() {
        // x₀ at its upper bound 0.5 and x₁ at its lower bound: forward and backward differences.
        let mut problem = Smooth { lower: vec![-1.0, -0.7], upper: vec![0.5, 2.0] };
        let x = [0.5, -0.7];
        let ((g, j), (g_exact, j_exact)) = (differences(&mut problem, &x), exact(&x));
        assert!(g.iter().zip(&g_exact).all(|(a, b)| (a - b).abs() < 1e-8));
        assert!((j - j_exact).amax() < 1e-8);
        // x₀ = 1: the evaluation beyond it fails, the backward difference is used.
        let mut problem = Smooth { lower: vec![f64::NEG_INFINITY; 2], upper: vec![f64::INFINITY; 2] };
        let x = [1.0, 0.2];
        let ((g, _), (g_exact, _)) = (differences(&mut problem, &x), exact(&x));
        assert!((g[0] - g_exact[0]).abs() < 1e-8);
    }

    #[test]
    fn a_fixed_variable_has_a_zero_column() {
        let mut problem = Smooth { lower: vec![0.2, f64::NEG_INFINITY], upper: vec![0.2, f64::INFINITY] };
        let (g, j) = differences(&mut problem, &[0.2, 0.1]);
        assert_eq!(g[0], 0.0);
        assert_eq!(j.column(0).amax(), 0.0);
    }
}
