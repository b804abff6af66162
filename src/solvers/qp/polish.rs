//! The active-set polish of a clarabel solution (see the documentation of [`qp`](super)).

use nalgebra::{DMatrix, DVector};

use super::rows::Activity;
use super::{DenseQp, QpSolution};

/// Slack allowed on ranges and multiplier signs when checking the polished point.
const CHECK: f64 = 1e-9;
/// In the second try, a multiplier below this (relative to the largest, at least 1) marks a
/// weakly active side, left out of the active set.
const WEAK: f64 = 1e-6;

/// Which constraint an active row is and the side it sits at (+1 upper, −1 lower, 0 both).
#[derive(Debug, Clone, Copy)]
struct Active {
    equality: bool,
    index: usize,
    value: f64,
    side: f64,
}

/// Replaces `solution` by the exact KKT point of its active set when that is a KKT point of
/// the whole QP. Tried first with every side clarabel reaches, then (for degenerate points,
/// e.g. more active rows than free variables) with only the sides whose clarabel multiplier
/// is not negligible.
pub(super) fn polish(qp: &DenseQp, solution: &mut QpSolution, activity: &Activity) {
    for weak_threshold in [None, Some(WEAK * largest_multiplier(solution))] {
        if let Some(polished) = polished(qp, solution, activity, weak_threshold) {
            *solution = polished;
            return;
        }
    }
}

fn largest_multiplier(solution: &QpSolution) -> f64 {
    let all = solution.equality_multipliers.iter().chain(&solution.inequality_multipliers).chain(&solution.bound_multipliers);
    all.fold(1.0, |largest, m| largest.max(m.abs()))
}

/// The polished solution for one rule of activity: a reached side counts when its
/// multiplier exceeds `weak_threshold` (any multiplier when `None`).
fn polished(qp: &DenseQp, solution: &QpSolution, activity: &Activity, weak_threshold: Option<f64>) -> Option<QpSolution> {
    let strong = |multiplier: f64| weak_threshold.is_none_or(|threshold| multiplier.abs() > threshold);
    let fixed = fixed_variables(qp, &activity.bounds, |k| strong(solution.bound_multipliers[k]));
    let active = active_rows(qp, &activity.rows, |i| strong(solution.inequality_multipliers[i]));
    let free: Vec<usize> = (0..fixed.len()).filter(|&k| fixed[k].is_none()).collect();
    let (x, y) = solve_active_set(qp, &fixed, &free, &active)?;
    let bound_multipliers = check(qp, &x, &y, &fixed, &active)?;
    let mut polished = solution.clone();
    polished.x.copy_from_slice(x.as_slice());
    polished.objective = qp.objective(&polished.x);
    polished.equality_multipliers.fill(0.0);
    polished.inequality_multipliers.fill(0.0);
    for (row, y) in active.iter().zip(y.iter()) {
        let target = if row.equality { &mut polished.equality_multipliers } else { &mut polished.inequality_multipliers };
        target[row.index] = *y;
    }
    polished.bound_multipliers.copy_from_slice(bound_multipliers.as_slice());
    polished.polished = true;
    Some(polished)
}

/// The bound each variable is fixed at: fixed variables and the active bounds.
fn fixed_variables(qp: &DenseQp, sides: &[f64], strong: impl Fn(usize) -> bool) -> Vec<Option<f64>> {
    let Some((lower, upper)) = qp.bounds else { return vec![None; sides.len()] };
    let at = |k: usize| match sides[k] {
        _ if lower[k] == upper[k] => Some(lower[k]),
        side if side > 0.0 && strong(k) => Some(upper[k]),
        side if side < 0.0 && strong(k) => Some(lower[k]),
        _ => None,
    };
    (0..sides.len()).map(at).collect()
}

/// The equality rows and the inequality rows at an active side.
fn active_rows(qp: &DenseQp, sides: &[f64], strong: impl Fn(usize) -> bool) -> Vec<Active> {
    let mut active = Vec::new();
    if let Some((_, rhs)) = qp.equalities {
        active.extend(rhs.iter().enumerate().map(|(index, &value)| Active { equality: true, index, value, side: 0.0 }));
    }
    if let Some((_, lower, upper)) = qp.inequalities {
        for (index, &side) in sides.iter().enumerate() {
            let at = match side {
                _ if lower[index] == upper[index] => Some((upper[index], 0.0)),
                side if side > 0.0 && strong(index) => Some((upper[index], 1.0)),
                side if side < 0.0 && strong(index) => Some((lower[index], -1.0)),
                _ => None,
            };
            active.extend(at.map(|(value, side)| Active { equality: false, index, value, side }));
        }
    }
    active
}

/// Row `row` of the active set's matrix.
fn row_matrix<'a>(qp: &DenseQp<'a>, row: &Active) -> &'a DMatrix<f64> {
    if row.equality {
        qp.equalities.expect("active equality rows exist").0
    } else {
        qp.inequalities.expect("active inequality rows exist").0
    }
}

/// P's entry (zero outside its block).
fn hessian(qp: &DenseQp, i: usize, j: usize) -> f64 {
    let k = qp.hessian.nrows();
    if i < k && j < k {
        0.5 * (qp.hessian[(i, j)] + qp.hessian[(j, i)])
    } else {
        0.0
    }
}

/// x and the active rows' multipliers y from
/// [P_FF  A_Fᵀ; A_F  0] [x_F; y] = [−q_F − P_FX x_X; b − A_X x_X] (X: fixed variables).
fn solve_active_set(qp: &DenseQp, fixed: &[Option<f64>], free: &[usize], active: &[Active]) -> Option<(DVector<f64>, DVector<f64>)> {
    let (nf, na) = (free.len(), active.len());
    let x_fixed = DVector::from_iterator(fixed.len(), fixed.iter().map(|f| f.unwrap_or(0.0)));
    let mut system = DMatrix::zeros(nf + na, nf + na);
    let mut rhs = DVector::zeros(nf + na);
    for (a, &i) in free.iter().enumerate() {
        for (b, &j) in free.iter().enumerate() {
            system[(a, b)] = hessian(qp, i, j);
        }
        let coupling: f64 = (0..fixed.len()).filter(|&j| fixed[j].is_some()).map(|j| hessian(qp, i, j) * x_fixed[j]).sum();
        rhs[a] = -qp.linear[i] - coupling;
    }
    for (r, row) in active.iter().enumerate() {
        let matrix = row_matrix(qp, row);
        for (a, &i) in free.iter().enumerate() {
            system[(nf + r, a)] = matrix[(row.index, i)];
            system[(a, nf + r)] = matrix[(row.index, i)];
        }
        let coupling: f64 = (0..fixed.len()).map(|j| matrix[(row.index, j)] * x_fixed[j]).sum();
        rhs[nf + r] = row.value - coupling;
    }
    let solution = if nf + na == 0 { rhs } else { system.lu().solve(&rhs)? };
    if solution.iter().any(|v| !v.is_finite()) {
        return None;
    }
    let mut x = x_fixed;
    for (a, &i) in free.iter().enumerate() {
        x[i] = solution[a];
    }
    Some((x, solution.rows(nf, na).into_owned()))
}

/// The bound multipliers ν = −(P x + q + Aᵀy) of the fixed variables when (x, y) is a KKT
/// point of the whole QP; `None` otherwise.
fn check(qp: &DenseQp, x: &DVector<f64>, y: &DVector<f64>, fixed: &[Option<f64>], active: &[Active]) -> Option<DVector<f64>> {
    let n = x.len();
    let sign_slack = CHECK * y.amax().max(1.0);
    let mut gradient = DVector::from_iterator(n, (0..n).map(|i| qp.linear[i] + (0..n).map(|j| hessian(qp, i, j) * x[j]).sum::<f64>()));
    for (row, &y) in active.iter().zip(y.iter()) {
        if row.side * y < -sign_slack {
            return None;
        }
        let matrix = row_matrix(qp, row);
        for j in 0..n {
            gradient[j] += y * matrix[(row.index, j)];
        }
    }
    if !inactive_rows_hold(qp, x, active) {
        return None;
    }
    let (lower, upper) = qp.bounds.unwrap_or((&[], &[]));
    let mut nu = DVector::zeros(n);
    let sign_slack = CHECK * gradient.amax().max(1.0);
    for k in 0..n {
        match fixed[k] {
            None if !lower.is_empty() && !within(x[k], lower[k], upper[k]) => return None,
            None => {}
            Some(value) => {
                nu[k] = -gradient[k];
                let side = if lower[k] == upper[k] { 0.0 } else if value == upper[k] { 1.0 } else { -1.0 };
                if side * nu[k] < -sign_slack {
                    return None;
                }
            }
        }
    }
    Some(nu)
}

fn within(value: f64, lower: f64, upper: f64) -> bool {
    value >= lower - CHECK * (1.0 + lower.abs()) && value <= upper + CHECK * (1.0 + upper.abs())
}

/// Every inequality row not in the active set within its range.
fn inactive_rows_hold(qp: &DenseQp, x: &DVector<f64>, active: &[Active]) -> bool {
    let Some((matrix, lower, upper)) = qp.inequalities else { return true };
    let values = matrix * x;
    let mut is_active = vec![false; lower.len()];
    for row in active.iter().filter(|row| !row.equality) {
        is_active[row.index] = true;
    }
    (0..lower.len()).all(|i| is_active[i] || within(values[i], lower[i], upper[i]))
}
