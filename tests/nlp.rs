//! The SQP solver on problems with known solutions: Hock–Schittkowski problems from their
//! standard starting points (optima from Hock & Schittkowski 1981, "Test Examples for
//! Nonlinear Programming Codes"), an inconsistent linearisation, infeasible problems, a
//! Chebyshev fit in epigraph form, evaluations that fail in part of the domain and random
//! convex QPs.

use nalgebra::{DMatrix, DVector};
use osim_tune::solvers::nlp::{EvaluationError, HessianMode, NlpError, NlpProblem, NlpSettings, NlpSolution, NlpStatus, Sqp};
use osim_tune::solvers::qp::{DenseQp, QpSettings, QpSolution, QpStatus};
use proptest::prelude::*;
use proptest::test_runner::RngSeed;

const INF: f64 = f64::INFINITY;

type Evaluation = Box<dyn FnMut(&[f64], &mut [f64]) -> Result<f64, EvaluationError>>;

/// A problem from closures, with finite-difference derivatives.
struct Closure {
    bounds: (Vec<f64>, Vec<f64>),
    constraint_bounds: (Vec<f64>, Vec<f64>),
    evaluation: Evaluation,
}

impl Closure {
    fn new(n: usize, constraint_bounds: (Vec<f64>, Vec<f64>), evaluation: impl FnMut(&[f64], &mut [f64]) -> f64 + 'static) -> Closure {
        let mut evaluation = evaluation;
        Closure { bounds: (vec![-INF; n], vec![INF; n]), constraint_bounds, evaluation: Box::new(move |x, c| Ok(evaluation(x, c))) }
    }

    fn bounded(mut self, lower: Vec<f64>, upper: Vec<f64>) -> Closure {
        self.bounds = (lower, upper);
        self
    }
}

impl NlpProblem for Closure {
    fn dimension(&self) -> usize {
        self.bounds.0.len()
    }

    fn bounds(&self) -> (Vec<f64>, Vec<f64>) {
        self.bounds.clone()
    }

    fn constraint_bounds(&self) -> (Vec<f64>, Vec<f64>) {
        self.constraint_bounds.clone()
    }

    fn evaluate(&mut self, x: &[f64], constraints: &mut [f64]) -> Result<f64, EvaluationError> {
        (self.evaluation)(x, constraints)
    }
}

fn equalities(m: usize) -> (Vec<f64>, Vec<f64>) {
    (vec![0.0; m], vec![0.0; m])
}

fn nonnegative(m: usize) -> (Vec<f64>, Vec<f64>) {
    (vec![0.0; m], vec![INF; m])
}

fn solve(problem: &mut impl NlpProblem, start: &[f64]) -> NlpSolution {
    solve_with(problem, start, NlpSettings::default())
}

fn solve_with(problem: &mut impl NlpProblem, start: &[f64], settings: NlpSettings) -> NlpSolution {
    Sqp::new(problem, settings).unwrap().solve(problem, start).unwrap()
}

/// Converged, with x and f within `tolerance` of the known optimum.
fn assert_optimum(solution: &NlpSolution, x: &[f64], f: f64, tolerance: f64) {
    assert_eq!(solution.status, NlpStatus::Converged, "{solution:#?}");
    let distance = solution.x.iter().zip(x).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
    assert!(distance <= tolerance, "x = {:?}, expected {x:?}", solution.x);
    assert!((solution.objective - f).abs() <= tolerance * f.abs().max(1.0), "f = {}, expected {f}", solution.objective);
    assert!(solution.constraint_violation <= 1e-8);
    assert!(solution.kkt_error <= 1e-8);
}

#[test]
fn hs6_equality_constrained_rosenbrock() {
    let mut problem = Closure::new(2, equalities(1), |x, c| {
        c[0] = 10.0 * (x[1] - x[0] * x[0]);
        (1.0 - x[0]).powi(2)
    });
    let solution = solve(&mut problem, &[-1.2, 1.0]);
    assert_optimum(&solution, &[1.0, 1.0], 0.0, 1e-6);
}

fn hs7() -> Closure {
    Closure::new(2, equalities(1), |x, c| {
        c[0] = (1.0 + x[0] * x[0]).powi(2) + x[1] * x[1] - 4.0;
        (1.0 + x[0] * x[0]).ln() - x[1]
    })
}

/// HS6 with exact derivatives and the exact Hessian of the Lagrangian
/// diag(2 − 20λ, 0), which is singular (and indefinite for λ > 0.1): the solver shifts it.
struct Hs6Exact;

impl NlpProblem for Hs6Exact {
    fn dimension(&self) -> usize {
        2
    }

    fn constraint_bounds(&self) -> (Vec<f64>, Vec<f64>) {
        equalities(1)
    }

    fn evaluate(&mut self, x: &[f64], c: &mut [f64]) -> Result<f64, EvaluationError> {
        c[0] = 10.0 * (x[1] - x[0] * x[0]);
        Ok((1.0 - x[0]).powi(2))
    }

    fn derivatives(&mut self, x: &[f64], gradient: &mut [f64], jacobian: &mut DMatrix<f64>) -> Result<(), EvaluationError> {
        gradient.copy_from_slice(&[-2.0 * (1.0 - x[0]), 0.0]);
        jacobian.copy_from_slice(&[-20.0 * x[0], 10.0]);
        Ok(())
    }

    fn has_hessian(&self) -> bool {
        true
    }

    fn hessian(&mut self, _: &[f64], multipliers: &[f64], hessian: &mut DMatrix<f64>) -> Result<(), EvaluationError> {
        hessian.copy_from_slice(&[2.0 - 20.0 * multipliers[0], 0.0, 0.0, 0.0]);
        Ok(())
    }
}

#[test]
fn a_singular_exact_hessian_is_shifted_to_positive_definite() {
    let solution = solve(&mut Hs6Exact, &[-1.2, 1.0]);
    assert_optimum(&solution, &[1.0, 1.0], 0.0, 1e-6);
    let bfgs = solve_with(&mut Hs6Exact, &[-1.2, 1.0], NlpSettings { hessian: HessianMode::Bfgs, ..NlpSettings::default() });
    assert_optimum(&bfgs, &[1.0, 1.0], 0.0, 1e-6);
}

#[test]
fn hs7_from_its_standard_start() {
    let solution = solve(&mut hs7(), &[2.0, 2.0]);
    assert_optimum(&solution, &[0.0, 3f64.sqrt()], -3f64.sqrt(), 1e-6);
}

#[test]
fn hs35_convex_quadratic_with_a_linear_inequality_and_bounds() {
    let mut problem = Closure::new(3, nonnegative(1), |x, c| {
        c[0] = 3.0 - x[0] - x[1] - 2.0 * x[2];
        9.0 - 8.0 * x[0] - 6.0 * x[1] - 4.0 * x[2] + 2.0 * x[0] * x[0] + 2.0 * x[1] * x[1] + x[2] * x[2] + 2.0 * x[0] * x[1] + 2.0 * x[0] * x[2]
    })
    .bounded(vec![0.0; 3], vec![INF; 3]);
    let solution = solve(&mut problem, &[0.5, 0.5, 0.5]);
    assert_optimum(&solution, &[4.0 / 3.0, 7.0 / 9.0, 4.0 / 9.0], 1.0 / 9.0, 1e-6);
    // The inequality is active: λ ≤ 0 (its lower side), ∇f + Jᵀλ = 0 with J = (−1, −1, −2).
    assert!(solution.multipliers.constraints[0] < 0.0);
    assert!((solution.multipliers.constraints[0] + 2.0 / 9.0).abs() < 1e-6);
}

#[test]
fn hs40_three_nonlinear_equalities() {
    let mut problem = Closure::new(4, equalities(3), |x, c| {
        c[0] = x[0].powi(3) + x[1] * x[1] - 1.0;
        c[1] = x[0] * x[0] * x[3] - x[2];
        c[2] = x[3] * x[3] - x[1];
        -x[0] * x[1] * x[2] * x[3]
    });
    let solution = solve(&mut problem, &[0.8; 4]);
    let expected = [2f64.powf(-1.0 / 3.0), 2f64.powf(-0.5), 2f64.powf(-11.0 / 12.0), 2f64.powf(-0.25)];
    assert_optimum(&solution, &expected, -0.25, 1e-6);
}

fn hs71() -> Closure {
    let constraint_bounds = (vec![25.0, 40.0], vec![INF, 40.0]);
    Closure::new(4, constraint_bounds, |x, c| {
        c[0] = x[0] * x[1] * x[2] * x[3];
        c[1] = x.iter().map(|v| v * v).sum();
        x[0] * x[3] * (x[0] + x[1] + x[2]) + x[2]
    })
    .bounded(vec![1.0; 4], vec![5.0; 4])
}

#[test]
fn hs71_mixed_constraints_and_bounds() {
    let solution = solve(&mut hs71(), &[1.0, 5.0, 5.0, 1.0]);
    assert_optimum(&solution, &[1.0, 4.7429994, 3.8211503, 1.3794082], 17.0140173, 1e-6);
    // x₀ sits at its lower bound: ν₀ ≤ 0; the product constraint at its lower side: λ₀ ≤ 0.
    assert!(solution.multipliers.bounds[0] < 0.0);
    assert!(solution.multipliers.constraints[0] < 0.0);
}

#[test]
fn hs76_linear_inequalities_with_an_active_bound() {
    let mut problem = Closure::new(4, nonnegative(3), |x, c| {
        c[0] = 5.0 - x[0] - 2.0 * x[1] - x[2] - x[3];
        c[1] = 4.0 - 3.0 * x[0] - x[1] - 2.0 * x[2] + x[3];
        c[2] = x[1] + 4.0 * x[2] - 1.5;
        x[0] * x[0] + 0.5 * x[1] * x[1] + x[2] * x[2] + 0.5 * x[3] * x[3] - x[0] * x[2] + x[2] * x[3] - x[0] - 3.0 * x[1] + x[2] - x[3]
    })
    .bounded(vec![0.0; 4], vec![INF; 4]);
    let solution = solve(&mut problem, &[0.5; 4]);
    assert_optimum(&solution, &[3.0 / 11.0, 23.0 / 11.0, 0.0, 6.0 / 11.0], -103.0 / 22.0, 1e-6);
    assert_eq!(solution.x[2], 0.0, "the active bound is met exactly");
}

fn hs100() -> Closure {
    Closure::new(7, nonnegative(4), |x, c| {
        c[0] = 127.0 - 2.0 * x[0].powi(2) - 3.0 * x[1].powi(4) - x[2] - 4.0 * x[3].powi(2) - 5.0 * x[4];
        c[1] = 282.0 - 7.0 * x[0] - 3.0 * x[1] - 10.0 * x[2].powi(2) - x[3] + x[4];
        c[2] = 196.0 - 23.0 * x[0] - x[1].powi(2) - 6.0 * x[5].powi(2) + 8.0 * x[6];
        c[3] = -4.0 * x[0].powi(2) - x[1].powi(2) + 3.0 * x[0] * x[1] - 2.0 * x[2].powi(2) - 5.0 * x[5] + 11.0 * x[6];
        (x[0] - 10.0).powi(2) + 5.0 * (x[1] - 12.0).powi(2) + x[2].powi(4) + 3.0 * (x[3] - 11.0).powi(2) + 10.0 * x[4].powi(6) + 7.0 * x[5].powi(2)
            + x[6].powi(4)
            - 4.0 * x[5] * x[6]
            - 10.0 * x[5]
            - 8.0 * x[6]
    })
}

const HS100_START: [f64; 7] = [1.0, 2.0, 0.0, 4.0, 0.0, 1.0, 1.0];

#[test]
fn hs100_seven_variables_four_nonlinear_inequalities() {
    let solution = solve(&mut hs100(), &HS100_START);
    let expected = [2.330499, 1.951372, -0.4775414, 4.365726, -0.6244870, 1.038131, 1.594227];
    assert_optimum(&solution, &expected, 680.6300573, 1e-5);
}

/// Uniform numbers in [−1, 1) from a seeded linear congruential generator.
fn uniform(mut seed: u64) -> impl FnMut() -> f64 {
    move || {
        seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        ((seed >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }
}

#[test]
fn seeded_random_starts_reach_kkt_points() {
    let mut draw = uniform(2024);
    for _ in 0..20 {
        // HS71 has other local minima; each start must end at a KKT point inside the bounds.
        let start: Vec<f64> = (0..4).map(|_| 3.0 + 2.0 * draw()).collect();
        let solution = solve(&mut hs71(), &start);
        assert_eq!(solution.status, NlpStatus::Converged, "HS71 from {start:?}");
        assert!(solution.x.iter().all(|x| (1.0..=5.0).contains(x)));
        let start: Vec<f64> = HS100_START.iter().map(|x| x + 1.5 * draw()).collect();
        let solution = solve(&mut hs100(), &start);
        assert_eq!(solution.status, NlpStatus::Converged, "HS100 from {start:?}");
        assert!((solution.objective - 680.6300573).abs() < 1e-5);
        let start: Vec<f64> = (0..2).map(|_| 3.0 * draw()).collect();
        let solution = solve(&mut hs7(), &start);
        assert_eq!(solution.status, NlpStatus::Converged, "HS7 from {start:?}");
        // The minimum −√3 at (0, √3) and the local minimum √3 at (0, −√3).
        assert!((solution.objective.abs() - 3f64.sqrt()).abs() < 1e-7 && solution.x[0].abs() < 1e-6);
    }
}

#[test]
fn an_inconsistent_linearisation_at_the_start_is_handled_by_elastic_mode() {
    // x₀² + x₁² ≥ 8 within −1 ≤ x ≤ 3, nearest to (1, 1): the solution is (2, 2). At the start
    // (0.5, 0.5) the linearisation asks for d₀ + d₁ ≥ 7.5 while the bounds allow d ≤ 2.5.
    let start = [0.5, 0.5];
    let (lower, upper) = (vec![-1.0; 2], vec![3.0; 2]);
    let jacobian = DMatrix::from_row_slice(1, 2, &[2.0 * start[0], 2.0 * start[1]]);
    let identity = DMatrix::identity(2, 2);
    let step_lower: Vec<f64> = lower.iter().zip(&start).map(|(l, x)| l - x).collect();
    let step_upper: Vec<f64> = upper.iter().zip(&start).map(|(u, x)| u - x).collect();
    let linearised = DenseQp::new(&identity, &[0.0, 0.0])
        .and_then(|qp| qp.with_inequalities(&jacobian, &[8.0 - 0.5], &[INF]))
        .and_then(|qp| qp.with_bounds(&step_lower, &step_upper))
        .unwrap();
    assert_eq!(linearised.solve(&QpSettings::default()).status, QpStatus::Infeasible);

    let mut problem = Closure::new(2, (vec![8.0], vec![INF]), |x, c| {
        c[0] = x[0] * x[0] + x[1] * x[1];
        (x[0] - 1.0).powi(2) + (x[1] - 1.0).powi(2)
    })
    .bounded(lower, upper);
    let solution = solve(&mut problem, &start);
    assert_optimum(&solution, &[2.0, 2.0], 2.0, 1e-7);
}

/// x₀ + x₁ = 1 and x₀ + x₁² = 1 with x₁ ≥ 0.3: only (0, 1) is feasible. At x₁ = 0.5 both
/// gradients are (1, 1) while the values differ: the linearisation is inconsistent. Below
/// x₁ = 0.5 the violation x₁ − x₁² (for x₀ between 1 − x₁ and 1 − x₁²) falls towards the bound.
fn parallel_gradients() -> Closure {
    Closure::new(2, equalities(2), |x, c| {
        c[0] = x[0] + x[1] - 1.0;
        c[1] = x[0] + x[1] * x[1] - 1.0;
        (x[0] - 2.0).powi(2) + x[1] * x[1]
    })
    .bounded(vec![-INF, 0.3], vec![INF, INF])
}

#[test]
fn parallel_constraint_gradients_at_the_start() {
    let solution = solve(&mut parallel_gradients(), &[0.0, 0.5]);
    assert_optimum(&solution, &[0.0, 1.0], 5.0, 1e-7);
}

#[test]
fn a_feasible_problem_is_locally_infeasible_from_a_bad_start() {
    // From x₁ = 0.35 the violation is least, 0.21, at the bound x₁ = 0.3 for any x₀ in
    // [0.7, 0.91]: a local minimiser of the violation.
    let solution = solve(&mut parallel_gradients(), &[0.8, 0.35]);
    assert_eq!(solution.status, NlpStatus::LocallyInfeasible, "{solution:#?}");
    assert_eq!(solution.x[1], 0.3);
    assert!((0.7 - 1e-9..=0.91 + 1e-9).contains(&solution.x[0]), "{:?}", solution.x);
}

/// x₀² + x₁² = 1 with x₀ ≥ 2: the violation is least, and stationary, at (2, 0).
fn circle_beyond_a_bound() -> Closure {
    Closure::new(2, equalities(1), |x, c| {
        c[0] = x[0] * x[0] + x[1] * x[1] - 1.0;
        x[0] + x[1]
    })
    .bounded(vec![2.0, -INF], vec![INF, INF])
}

/// x² + 1 = 0 has no solution; its violation is stationary at x = 0, which the objective
/// (x − 1)² pulls away from.
fn no_real_roots() -> Closure {
    Closure::new(1, equalities(1), |x, c| {
        c[0] = x[0] * x[0] + 1.0;
        (x[0] - 1.0).powi(2)
    })
}

#[test]
fn a_circle_beyond_a_bound_is_locally_infeasible() {
    let solution = solve(&mut circle_beyond_a_bound(), &[3.0, 1.0]);
    assert_eq!(solution.status, NlpStatus::LocallyInfeasible, "{solution:#?}");
    assert!(solution.x[0] == 2.0 && solution.x[1].abs() < 1e-8, "{:?}", solution.x);
    assert!((solution.constraint_violation - 3.0).abs() < 1e-12);
    // The certificate: Jᵀλ̂ + ν̂ = 0 with λ̂ = 1 (c above its bound), ν̂₀ = −4 (x₀ at its lower bound).
    assert_eq!(solution.multipliers.constraints, vec![1.0]);
    assert!((solution.multipliers.bounds[0] + 4.0).abs() < 1e-8, "{:?}", solution.multipliers);
}

#[test]
fn a_constraint_without_real_roots_is_locally_infeasible() {
    let solution = solve(&mut no_real_roots(), &[2.0]);
    assert_eq!(solution.status, NlpStatus::LocallyInfeasible, "{solution:#?}");
    assert!(solution.x[0].abs() < 1e-8, "{:?}", solution.x);
}

#[test]
fn infeasible_problems_are_detected_from_seeded_random_starts() {
    let mut draw = uniform(5);
    for _ in 0..20 {
        let start = [2.0 + 3.0 * draw().abs(), 3.0 * draw()];
        let solution = solve(&mut circle_beyond_a_bound(), &start);
        assert_eq!(solution.status, NlpStatus::LocallyInfeasible, "circle from {start:?}");
        assert!((solution.constraint_violation - 3.0).abs() < 1e-8);
        let start = [5.0 * draw()];
        let solution = solve(&mut no_real_roots(), &start);
        assert_eq!(solution.status, NlpStatus::LocallyInfeasible, "x² + 1 from {start:?}");
        assert!(solution.x[0].abs() < 1e-8);
    }
}

#[test]
fn chebyshev_fit_of_a_line_to_three_points_in_epigraph_form() {
    // min t over (a, b, t) s.t. −t ≤ yₖ − a − b tₖ ≤ t for (0, 0), (1, 2), (3, 1). By the
    // alternation theorem the residuals are −h, +h, −h: a = 5/6, b = 1/3, t = h = 5/6.
    let points = [(0.0, 0.0), (1.0, 2.0), (3.0, 1.0)];
    let bounds = (vec![-INF, 0.0, -INF, 0.0, -INF, 0.0], vec![0.0, INF, 0.0, INF, 0.0, INF]);
    let mut problem = Closure::new(3, bounds, move |x, c| {
        for (k, (time, value)) in points.iter().enumerate() {
            let residual = value - x[0] - x[1] * time;
            c[2 * k] = residual - x[2];
            c[2 * k + 1] = residual + x[2];
        }
        x[2]
    });
    let solution = solve(&mut problem, &[0.0, 0.0, 0.0]);
    assert_optimum(&solution, &[5.0 / 6.0, 1.0 / 3.0, 5.0 / 6.0], 5.0 / 6.0, 1e-8);
    // Multipliers of the three active sides sum to 1 in magnitude (∂/∂t: 1 − Σ|λ| = 0).
    let total: f64 = solution.multipliers.constraints.iter().map(|l| l.abs()).sum();
    assert!((total - 1.0).abs() < 1e-7);
}

/// min x₀² + x₁² s.t. x₀ + x₁ ≥ 1.2, whose evaluation fails for x₀ < 0.1 (as an equilibrium
/// that cannot be computed would).
struct FailingBelow {
    failures: usize,
}

impl NlpProblem for FailingBelow {
    fn dimension(&self) -> usize {
        2
    }

    fn constraint_bounds(&self) -> (Vec<f64>, Vec<f64>) {
        (vec![1.2], vec![INF])
    }

    fn evaluate(&mut self, x: &[f64], constraints: &mut [f64]) -> Result<f64, EvaluationError> {
        if x[0] < 0.1 {
            self.failures += 1;
            return Err(EvaluationError::new("no equilibrium"));
        }
        constraints[0] = x[0] + x[1];
        Ok(x[0] * x[0] + x[1] * x[1])
    }
}

#[test]
fn the_line_search_backs_off_from_failing_evaluations() {
    let mut problem = FailingBelow { failures: 0 };
    let solution = solve(&mut problem, &[3.0, 0.2]);
    assert_optimum(&solution, &[0.6, 0.6], 0.72, 1e-7);
    assert!(problem.failures > 0, "the first full step leaves the domain");
}

#[test]
fn a_start_point_that_cannot_be_evaluated_is_a_status() {
    let mut problem = FailingBelow { failures: 0 };
    let solution = solve(&mut problem, &[0.0, 1.0]);
    assert_eq!(solution.status, NlpStatus::EvaluationFailed);
    assert_eq!(solution.iterations, 0);
}

#[test]
fn not_a_number_counts_as_a_failed_evaluation() {
    // f = √x₀ + (x₁ − 1)² + … is NaN for x₀ < 0; the solution x₀ = 0.25 is inside.
    let mut problem = Closure::new(2, (vec![], vec![]), |x, _| (x[0] - 1.0).powi(2) + x[0].sqrt() * 0.0 + (x[1] - 1.0).powi(2) - x[0].ln());
    let solution = solve(&mut problem, &[3.0, 0.0]);
    // f'(x₀) = 2(x₀ − 1) − 1/x₀ = 0 → x₀ = (1 + √3)/2.
    let expected = (1.0 + 3f64.sqrt()) / 2.0;
    assert_optimum(&solution, &[expected, 1.0], (expected - 1.0).powi(2) - expected.ln(), 1e-7);
}

#[test]
fn limits_of_the_iterations_are_a_status() {
    let mut problem = hs71();
    let settings = NlpSettings { max_iterations: 2, ..NlpSettings::default() };
    let solution = solve_with(&mut problem, &[1.0, 5.0, 5.0, 1.0], settings);
    assert_eq!(solution.status, NlpStatus::MaxIterations);
    assert_eq!(solution.iterations, 2);
    assert_eq!(solution.history.len(), 3);
    assert!(solution.x.iter().all(|&x| (1.0..=5.0).contains(&x)), "iterates stay inside the bounds");
}

#[test]
fn building_checks_dimensions_bounds_and_settings() {
    let mut problem = hs71().bounded(vec![1.0; 4], vec![5.0; 3]);
    assert!(matches!(Sqp::new(&problem, NlpSettings::default()), Err(NlpError::Dimension { .. })));
    problem = hs71().bounded(vec![1.0, 6.0, 1.0, 1.0], vec![5.0; 4]);
    assert!(matches!(Sqp::new(&problem, NlpSettings::default()), Err(NlpError::Range { index: 1, .. })));
    problem = hs71();
    problem.constraint_bounds = (vec![25.0, 40.0], vec![INF, f64::NAN]);
    assert!(matches!(Sqp::new(&problem, NlpSettings::default()), Err(NlpError::Range { .. })));
    problem = hs71();
    let settings = NlpSettings { tolerance: -1.0, ..NlpSettings::default() };
    assert!(matches!(Sqp::new(&problem, settings), Err(NlpError::Setting { name: "tolerance" })));
    let mut solver = Sqp::new(&problem, NlpSettings::default()).unwrap();
    assert!(matches!(solver.solve(&mut problem, &[1.0; 3]), Err(NlpError::Dimension { .. })));
    assert!(matches!(solver.solve(&mut problem, &[1.0, f64::NAN, 1.0, 1.0]), Err(NlpError::StartPoint { index: 1, .. })));
}

/// min ½xᵀPx + qᵀx s.t. A x = b, l ≤ G x ≤ u, bounds — with exact derivatives and Hessian.
struct ConvexQp {
    p: DMatrix<f64>,
    q: DVector<f64>,
    rows: DMatrix<f64>,
    row_lower: Vec<f64>,
    row_upper: Vec<f64>,
    lower: Vec<f64>,
    upper: Vec<f64>,
}

impl NlpProblem for ConvexQp {
    fn dimension(&self) -> usize {
        self.q.len()
    }

    fn bounds(&self) -> (Vec<f64>, Vec<f64>) {
        (self.lower.clone(), self.upper.clone())
    }

    fn constraint_bounds(&self) -> (Vec<f64>, Vec<f64>) {
        (self.row_lower.clone(), self.row_upper.clone())
    }

    fn evaluate(&mut self, x: &[f64], constraints: &mut [f64]) -> Result<f64, EvaluationError> {
        let x = DVector::from_column_slice(x);
        constraints.copy_from_slice((&self.rows * &x).as_slice());
        Ok(0.5 * x.dot(&(&self.p * &x)) + self.q.dot(&x))
    }

    fn derivatives(&mut self, x: &[f64], gradient: &mut [f64], jacobian: &mut DMatrix<f64>) -> Result<(), EvaluationError> {
        let x = DVector::from_column_slice(x);
        gradient.copy_from_slice((&self.p * &x + &self.q).as_slice());
        jacobian.copy_from(&self.rows);
        Ok(())
    }

    fn has_hessian(&self) -> bool {
        true
    }

    fn hessian(&mut self, _: &[f64], _: &[f64], hessian: &mut DMatrix<f64>) -> Result<(), EvaluationError> {
        hessian.copy_from(&self.p);
        Ok(())
    }
}

/// A random convex QP around a feasible point `center` (first `equalities` rows equalities).
fn convex_qp(n: usize, equalities: usize, inequalities: usize, values: &[f64]) -> ConvexQp {
    let mut next = values.iter().copied().cycle();
    let mut draw = move || next.next().unwrap();
    let l = DMatrix::from_fn(n, n, |_, _| draw());
    let p = &l * l.transpose() + DMatrix::identity(n, n) * 0.1;
    let q = DVector::from_fn(n, |_, _| 5.0 * draw());
    let center = DVector::from_fn(n, |_, _| draw());
    let m = equalities + inequalities;
    let rows = DMatrix::from_fn(m, n, |_, _| draw());
    let at_center = &rows * &center;
    let (mut row_lower, mut row_upper) = (vec![0.0; m], vec![0.0; m]);
    for i in 0..m {
        if i < equalities {
            (row_lower[i], row_upper[i]) = (at_center[i], at_center[i]);
        } else {
            (row_lower[i], row_upper[i]) = (at_center[i] - 0.5 - draw().abs(), if i % 2 == 0 { INF } else { at_center[i] + 0.5 });
        }
    }
    let lower = center.iter().map(|c| c - 1.0).collect();
    let upper = center.iter().enumerate().map(|(k, c)| if k % 3 == 0 { INF } else { c + 1.0 + draw().abs() }).collect();
    ConvexQp { p, q, rows, row_lower, row_upper, lower, upper }
}

/// The QP solved directly by clarabel, the reference of the SQP's answer.
fn clarabel_optimum(problem: &ConvexQp) -> QpSolution {
    DenseQp::new(&problem.p, problem.q.as_slice())
        .unwrap()
        .with_inequalities(&problem.rows, &problem.row_lower, &problem.row_upper)
        .unwrap()
        .with_bounds(&problem.lower, &problem.upper)
        .unwrap()
        .solve(&QpSettings::default())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, rng_seed: RngSeed::Fixed(20240611), failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn convex_qps_converge_in_one_or_two_iterations_to_clarabels_optimum(
        n in 2usize..7,
        equalities in 0usize..2,
        inequalities in 0usize..5,
        values in proptest::collection::vec(-1.0f64..1.0, 16),
        start in proptest::collection::vec(-2.0f64..2.0, 7),
    ) {
        let mut problem = convex_qp(n, equalities, inequalities, &values);
        let reference = clarabel_optimum(&problem);
        prop_assert!(reference.status.is_solved());
        let solution = solve(&mut problem, &start[..n]);
        prop_assert_eq!(solution.status, NlpStatus::Converged);
        prop_assert!(solution.iterations <= 2, "{} iterations {:#?}", solution.iterations, solution);
        // x only to 10⁻⁶: where a constraint is weakly active (zero multiplier) clarabel’s
        // interior point solution is accurate only to about the square root of its tolerance.
        let distance = solution.x.iter().zip(&reference.x).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
        prop_assert!(distance < 1e-6, "x = {:?}, clarabel {:?}", solution.x, reference.x);
        prop_assert!(solution.objective <= reference.objective + 1e-9 * reference.objective.abs().max(1.0));
        prop_assert!(solution.objective >= reference.objective - 1e-8 * reference.objective.abs().max(1.0));
    }
}

#[test]
fn bfgs_also_solves_a_problem_that_has_an_exact_hessian() {
    let values: Vec<f64> = (0..16).map(|k| ((k * 7 % 11) as f64 - 5.0) / 5.0).collect();
    let mut problem = convex_qp(5, 1, 3, &values);
    let settings = NlpSettings { hessian: HessianMode::Bfgs, ..NlpSettings::default() };
    let solution = solve_with(&mut problem, &[0.0; 5], settings);
    assert_eq!(solution.status, NlpStatus::Converged);
    assert!(solution.iterations > 2, "BFGS needs more than the exact Newton step");
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 32, rng_seed: RngSeed::Fixed(7), failure_persistence: None, ..ProptestConfig::default() })]

    /// With BFGS instead of the exact Hessian the solver needs more iterations, and reaches the
    /// same optimum.
    #[test]
    fn convex_qps_with_bfgs_reach_clarabels_optimum(
        n in 2usize..7,
        equalities in 0usize..3,
        inequalities in 0usize..6,
        values in proptest::collection::vec(-1.0f64..1.0, 16),
        start in proptest::collection::vec(-2.0f64..2.0, 7),
    ) {
        let mut problem = convex_qp(n, equalities, inequalities, &values);
        let reference = clarabel_optimum(&problem);
        prop_assume!(reference.status.is_solved());
        let settings = NlpSettings { hessian: HessianMode::Bfgs, ..NlpSettings::default() };
        let solution = solve_with(&mut problem, &start[..n], settings);
        prop_assert_eq!(solution.status, NlpStatus::Converged, "{:#?}", solution);
        let distance = solution.x.iter().zip(&reference.x).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
        prop_assert!(distance < 1e-6, "x = {:?}, clarabel {:?}", solution.x, reference.x);
    }
}

/// A problem shaped like functional scaling: 58 factors x ∈ [0.5, 2], slack s, epigraph t;
/// 80 nonlinear rows held in the band |cᵢ(x)| ≤ s, 20 epigraph rows t ≥ (Mₖ(x) − M̂ₖ)²,
/// 10 linear rows; minimise s + t.
struct ScalingLike {
    a: DMatrix<f64>,
    b: DMatrix<f64>,
    targets: Vec<f64>,
    evaluations: usize,
}

impl ScalingLike {
    const FACTORS: usize = 58;
    const BAND: usize = 80;
    const EPIGRAPH: usize = 20;
    const LINEAR: usize = 10;

    fn new() -> ScalingLike {
        let mut seed = 12345u64;
        let mut draw = move || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            ((seed >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
        };
        let a = DMatrix::from_fn(Self::BAND, Self::FACTORS, |_, _| draw());
        let b = DMatrix::from_fn(Self::EPIGRAPH, Self::FACTORS, |_, _| draw());
        let targets = (0..Self::EPIGRAPH).map(|_| 0.5 * draw()).collect();
        ScalingLike { a, b, targets, evaluations: 0 }
    }
}

impl NlpProblem for ScalingLike {
    fn dimension(&self) -> usize {
        Self::FACTORS + 2
    }

    fn bounds(&self) -> (Vec<f64>, Vec<f64>) {
        let mut lower = vec![0.5; Self::FACTORS];
        let mut upper = vec![2.0; Self::FACTORS];
        lower.extend([0.0, 0.0]);
        upper.extend([INF, INF]);
        (lower, upper)
    }

    fn constraint_bounds(&self) -> (Vec<f64>, Vec<f64>) {
        let rows = 2 * Self::BAND + Self::EPIGRAPH;
        let mut lower: Vec<f64> = (0..rows).map(|i| if i < 2 * Self::BAND && i % 2 == 0 { -INF } else { 0.0 }).collect();
        let mut upper: Vec<f64> = (0..rows).map(|i| if i < 2 * Self::BAND && i % 2 == 0 { 0.0 } else { INF }).collect();
        lower.extend(vec![-1.0; Self::LINEAR]);
        upper.extend(vec![1.0; Self::LINEAR]);
        (lower, upper)
    }

    fn evaluate(&mut self, x: &[f64], c: &mut [f64]) -> Result<f64, EvaluationError> {
        self.evaluations += 1;
        let (factors, s, t) = (&x[..Self::FACTORS], x[Self::FACTORS], x[Self::FACTORS + 1]);
        for i in 0..Self::BAND {
            let value: f64 = (0..Self::FACTORS).map(|j| self.a[(i, j)] * (factors[j] - 1.0) * (1.0 + 0.3 * factors[j].ln())).sum::<f64>() / 10.0;
            c[2 * i] = value - s;
            c[2 * i + 1] = value + s;
        }
        for k in 0..Self::EPIGRAPH {
            let moment: f64 = (0..Self::FACTORS).map(|j| self.b[(k, j)] * factors[j].sqrt()).sum::<f64>() / 10.0;
            c[2 * Self::BAND + k] = t - (moment - self.targets[k]).powi(2);
        }
        for l in 0..Self::LINEAR {
            c[2 * Self::BAND + Self::EPIGRAPH + l] = factors[l] - factors[l + Self::LINEAR];
        }
        Ok(s + t)
    }
}

#[test]
fn a_problem_of_the_functional_scaling_size_is_solved_quickly() {
    let mut problem = ScalingLike::new();
    let mut start = vec![1.2; ScalingLike::FACTORS];
    start.extend([1.0, 1.0]);
    let begin = std::time::Instant::now();
    let solution = solve(&mut problem, &start);
    let elapsed = begin.elapsed();
    assert_eq!(solution.status, NlpStatus::Converged, "{:?}", solution.history);
    assert!(solution.iterations <= 40, "{} iterations", solution.iterations);
    // Central differences (up to 2n = 120 evaluations per Jacobian, fewer at active bounds)
    // make nearly all of the evaluations.
    assert!(problem.evaluations >= 10 * solution.evaluations);
    assert!(elapsed.as_secs_f64() < 10.0, "{elapsed:?}");
}

/// min t² with |x_i − y_i| ≤ t (an exact fit, optimum f = 0): with `objective_target` 0.1
/// the solve stops at the first feasible iterate with t ≤ 0.32, before the KKT test would.
#[test]
fn objective_target_stops_at_a_small_enough_objective() {
    let data = [0.3, -1.2, 2.5];
    let inf = f64::INFINITY;
    let rows = (vec![-inf, -inf, -inf, data[0], data[1], data[2]], vec![data[0], data[1], data[2], inf, inf, inf]);
    let fit = move || {
        Closure::new(4, rows.clone(), move |x, c| {
            for i in 0..3 {
                c[i] = x[i] - x[3];
                c[i + 3] = x[i] + x[3];
            }
            x[3] * x[3]
        })
    };
    let start = [0.0, 0.0, 0.0, 3.0];
    let full = solve(&mut fit(), &start);
    assert_eq!(full.status, NlpStatus::Converged);
    let settings = NlpSettings { objective_target: 0.1, ..NlpSettings::default() };
    let stopped = solve_with(&mut fit(), &start, settings);
    assert_eq!(stopped.status, NlpStatus::ObjectiveTarget, "{stopped:#?}");
    assert!(stopped.objective <= 0.1 && stopped.objective > full.objective, "{} vs {}", stopped.objective, full.objective);
    assert!(stopped.constraint_violation <= 1e-8 && stopped.iterations < full.iterations);
}

/// f = (x − 1)⁴ + c with its exact gradient: Newton-like steps approach x = 1 by a steady
/// factor, so f − c falls geometrically and the gradient stays above any tight tolerance for
/// many iterations.
struct Quartic {
    offset: f64,
}

impl NlpProblem for Quartic {
    fn dimension(&self) -> usize {
        1
    }

    fn constraint_bounds(&self) -> (Vec<f64>, Vec<f64>) {
        (vec![], vec![])
    }

    fn evaluate(&mut self, x: &[f64], _: &mut [f64]) -> Result<f64, EvaluationError> {
        Ok((x[0] - 1.0).powi(4) + self.offset)
    }

    fn derivatives(&mut self, x: &[f64], gradient: &mut [f64], _: &mut DMatrix<f64>) -> Result<(), EvaluationError> {
        gradient[0] = 4.0 * (x[0] - 1.0).powi(3);
        Ok(())
    }
}

/// A KKT tolerance the quartic cannot meet soon; a stall over 5 iterations at 10⁻⁶.
fn stall_settings() -> NlpSettings {
    NlpSettings { tolerance: 1e-14, stall_iterations: 5, stall_tolerance: 1e-6, ..NlpSettings::default() }
}

/// Above a floor c = 3 the objective stops changing, relative to itself, long before the
/// gradient meets a tight tolerance: the solve ends `ObjectiveStalled` at the first iterate
/// whose f moved by at most 10⁻⁶·f over 5 iterations.
#[test]
fn an_objective_that_stops_changing_is_a_stall() {
    let solution = solve_with(&mut Quartic { offset: 3.0 }, &[3.0], stall_settings());
    assert_eq!(solution.status, NlpStatus::ObjectiveStalled, "{solution:#?}");
    let f: Vec<f64> = solution.history.iter().map(|r| r.objective).collect();
    let moved = |k: usize| (f[k - 5] - f[k]).abs() / f[k];
    let last = f.len() - 1;
    assert!(moved(last) <= 1e-6, "{f:?}");
    assert!((5..last).all(|k| moved(k) > 1e-6), "stopped at the first stalled iterate: {f:?}");
    assert!(solution.kkt_error > 1e-14 && (solution.x[0] - 1.0).abs() > 1e-3, "a stall, not a KKT point: {solution:#?}");
}

/// The stall test is relative to f alone: an objective falling geometrically towards 0 moves
/// by nearly all of itself over any 5 iterations, however small it gets, and never stalls.
#[test]
fn an_objective_falling_towards_zero_never_stalls() {
    let solution = solve_with(&mut Quartic { offset: 0.0 }, &[3.0], NlpSettings { max_iterations: 60, ..stall_settings() });
    assert_ne!(solution.status, NlpStatus::ObjectiveStalled, "{solution:#?}");
    assert!(solution.objective < 1e-12, "{solution:#?}");
}
