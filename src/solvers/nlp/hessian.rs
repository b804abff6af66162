//! The Hessian model B of the QP subproblems: damped BFGS (Powell) or the problem's exact
//! Hessian of the Lagrangian made positive definite.

use nalgebra::{DMatrix, DVector};

use super::problem::{EvaluationError, NlpProblem};

/// Powell's damping keeps sᵀr ≥ 0.2 sᵀBs.
const DAMPING: f64 = 0.2;
/// First shift tried on an indefinite exact Hessian, relative to max(1, max |Hᵢⱼ|).
const FIRST_SHIFT: f64 = 1e-8;

/// B, always symmetric positive definite.
#[derive(Debug, Clone)]
pub(super) struct HessianModel {
    pub matrix: DMatrix<f64>,
    /// Whether a BFGS update has been made since the last reset.
    updated: bool,
}

impl HessianModel {
    pub fn new(n: usize) -> HessianModel {
        HessianModel { matrix: DMatrix::identity(n, n), updated: false }
    }

    /// B = I.
    pub fn reset(&mut self) {
        self.matrix.fill_with_identity();
        self.updated = false;
    }

    /// The damped BFGS update with step s and change y of the Lagrangian's gradient: with
    /// θ = 1 if sᵀy ≥ 0.2 sᵀBs, else 0.8 sᵀBs / (sᵀBs − sᵀy), and r = θy + (1 − θ)Bs,
    /// B ← B − Bs sᵀB / sᵀBs + r rᵀ / sᵀr. Before the first update B is scaled to
    /// (yᵀy / sᵀy) I when sᵀy > 0 (Shanno–Phua).
    pub fn bfgs_update(&mut self, s: &DVector<f64>, y: &DVector<f64>) {
        let sy = s.dot(y);
        if !self.updated && sy > 0.0 {
            self.matrix.fill_with_identity();
            self.matrix *= y.norm_squared() / sy;
        }
        let bs = &self.matrix * s;
        let sbs = s.dot(&bs);
        if sbs.is_nan() || sbs <= 0.0 || sbs.is_infinite() {
            return;
        }
        let theta = if sy >= DAMPING * sbs { 1.0 } else { (1.0 - DAMPING) * sbs / (sbs - sy) };
        let r = y * theta + &bs * (1.0 - theta);
        let sr = s.dot(&r);
        self.matrix.ger(-1.0 / sbs, &bs, &bs, 1.0);
        self.matrix.ger(1.0 / sr, &r, &r, 1.0);
        symmetrize(&mut self.matrix);
        self.updated = true;
        if self.matrix.iter().any(|v| !v.is_finite()) {
            self.reset();
        }
    }

    /// B = ∇²L(x, λ) + δI with the smallest δ ∈ {0, 10⁻⁸s, 10⁻⁷s, …} (s = max(1, max |Hᵢⱼ|))
    /// that makes B positive definite (Cholesky succeeds).
    pub fn exact<P: NlpProblem + ?Sized>(&mut self, problem: &mut P, x: &[f64], lambda: &[f64]) -> Result<(), EvaluationError> {
        problem.hessian(x, lambda, &mut self.matrix)?;
        if self.matrix.iter().any(|v| !v.is_finite()) {
            return Err(EvaluationError::new("the Hessian is not finite"));
        }
        symmetrize(&mut self.matrix);
        let scale = self.matrix.amax().max(1.0);
        let mut shift = 0.0;
        while self.matrix.clone().cholesky().is_none() {
            let next = if shift == 0.0 { FIRST_SHIFT * scale } else { 10.0 * shift };
            add_to_diagonal(&mut self.matrix, next - shift);
            shift = next;
        }
        Ok(())
    }
}

fn add_to_diagonal(matrix: &mut DMatrix<f64>, value: f64) {
    for k in 0..matrix.nrows() {
        matrix[(k, k)] += value;
    }
}

fn symmetrize(matrix: &mut DMatrix<f64>) {
    let n = matrix.nrows();
    for j in 0..n {
        for i in 0..j {
            let mean = 0.5 * (matrix[(i, j)] + matrix[(j, i)]);
            matrix[(i, j)] = mean;
            matrix[(j, i)] = mean;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bfgs_satisfies_the_secant_equation_when_curvature_is_positive() {
        let mut model = HessianModel::new(3);
        let s = DVector::from_vec(vec![1.0, 0.5, -0.25]);
        let y = DVector::from_vec(vec![2.0, 1.5, 0.1]);
        model.bfgs_update(&s, &y);
        assert!((&model.matrix * &s - &y).amax() < 1e-12);
        let s2 = DVector::from_vec(vec![0.0, 1.0, 1.0]);
        let y2 = DVector::from_vec(vec![0.3, 2.0, 1.0]);
        model.bfgs_update(&s2, &y2);
        assert!((&model.matrix * &s2 - &y2).amax() < 1e-12);
        assert!(model.matrix.clone().cholesky().is_some());
    }

    #[test]
    fn damping_keeps_the_model_positive_definite_under_negative_curvature() {
        let mut model = HessianModel::new(2);
        model.bfgs_update(&DVector::from_vec(vec![1.0, 0.0]), &DVector::from_vec(vec![-1.0, 0.2]));
        assert!(model.matrix.clone().cholesky().is_some());
    }

    /// ∇²L = [[1, 2], [2, 1]] (eigenvalues 3, −1).
    struct Indefinite;

    impl NlpProblem for Indefinite {
        fn dimension(&self) -> usize {
            2
        }

        fn constraint_bounds(&self) -> (Vec<f64>, Vec<f64>) {
            (vec![], vec![])
        }

        fn evaluate(&mut self, x: &[f64], _: &mut [f64]) -> Result<f64, EvaluationError> {
            Ok(0.5 * x[0] * x[0] + 2.0 * x[0] * x[1] + 0.5 * x[1] * x[1])
        }

        fn has_hessian(&self) -> bool {
            true
        }

        fn hessian(&mut self, _: &[f64], _: &[f64], hessian: &mut DMatrix<f64>) -> Result<(), EvaluationError> {
            hessian.copy_from_slice(&[1.0, 2.0, 2.0, 1.0]);
            Ok(())
        }
    }

    #[test]
    fn an_indefinite_exact_hessian_is_shifted_just_past_its_negative_eigenvalue() {
        let mut model = HessianModel::new(2);
        model.exact(&mut Indefinite, &[0.0, 0.0], &[]).unwrap();
        let shift = model.matrix[(0, 0)] - 1.0;
        // The shifts tried are 2·10⁻⁸·10ᵏ; the first above 1 is 2.
        assert!((shift - 2.0).abs() < 1e-12, "shift {shift}");
        assert!(model.matrix.clone().cholesky().is_some());
        assert_eq!(model.matrix[(0, 1)], 2.0);
    }
}
