//! The global search of the rest-curve fit. On its rest curve each estimated muscle has one
//! coordinate s, and the knee moment is a sum of per-muscle contributions,
//! M_t = M_fixed,t + Σ_j c_j(s_j, t). So each muscle's c_j(·, t) is tabulated once, with its
//! slope, on a uniform grid of s, and interpolated by cubic Hermite pieces: a surrogate
//! whose evaluation costs no equilibrium. On the surrogate, each group of muscles (the agonists
//! of one direction, on that direction's trials; a muscle active in no trial alone, on all) is
//! fitted by least squares from every point of a coarse lattice, the other groups held, and the
//! groups take turns; combinations of their minima are then fitted jointly. The distinct minima
//! found, best first, are the starts of the exact
//! refinement: the moment error has several basins with exact rest lengths (the gastrocnemii
//! trade L_opt against each other at nearly equal cost), and only a global search finds the
//! right one.

use super::knee_moment::{EstimatedMuscles, KneeMomentModel};
use super::rest_curve::RestCurve;
use nalgebra::{Cholesky, DMatrix, DVector};

/// Minima closer than this in every s are one.
const SAME_MINIMUM: f64 = 1e-3;
/// The surrogate's least squares: converged when no s moves more than this; iteration cap.
const SURROGATE_STEP_TOLERANCE: f64 = 1e-10;
const SURROGATE_ITERATIONS: usize = 200;
/// Passes of the whole search, each held at the best joint minimum of the last.
const MAX_PASSES: usize = 4;
/// Rounds of the groups taking turns.
const MAX_ROUNDS: usize = 4;

/// One muscle's contributions and their slopes on a uniform grid of s; `None` where the curve
/// or a trial's equilibrium does not exist.
#[derive(Debug, Clone)]
pub struct ContributionTable {
    /// First grid point and spacing in s.
    pub start: f64,
    pub spacing: f64,
    pub points: Vec<Option<TablePoint>>,
}

/// c(s_i, t) and its slopes ∂c/∂s from the left and from the right per trial, N·m (equal but at
/// the start of the rest curve's clamped branch, where the curve has a corner).
#[derive(Debug, Clone)]
pub struct TablePoint {
    pub value: Vec<f64>,
    pub left: Vec<f64>,
    pub right: Vec<f64>,
}

impl ContributionTable {
    /// The table on `steps` points over `range`, slopes by central differences of step `step`.
    /// Where the curve's clamped branch starts inside the range, the grid is shifted down (by
    /// less than a spacing) to have a point there, with one-sided slopes, so that no cubic
    /// piece spans the corner.
    pub fn compute(model: &KneeMomentModel, workspace: &mut EstimatedMuscles, curve: &RestCurve, range: [f64; 2], steps: usize, step: f64) -> ContributionTable {
        let spacing = (range[1] - range[0]) / (steps - 1).max(1) as f64;
        let corner = curve.clamp().map(|(s, _)| s).filter(|s| *s > range[0] && *s < range[1]);
        let start = corner.map_or(range[0], |corner| corner - ((corner - range[0]) / spacing).ceil() * spacing);
        let mut hint = curve.origin().tendon_slack_length;
        let points = (0..steps)
            .map(|i| {
                let s = start + spacing * i as f64;
                let mut at = |s: f64| {
                    let mut out = vec![0.0; model.trials().len()];
                    curve.contributions(model, workspace, s, &mut hint, &mut out).then_some(out)
                };
                let (value, plus, minus) = (at(s)?, at(s + step)?, at(s - step)?);
                let slope = |a: &[f64], b: &[f64], h: f64| -> Vec<f64> { a.iter().zip(b).map(|(a, b)| (a - b) / h).collect() };
                Some(match corner {
                    Some(corner) if (s - corner).abs() < 1e-9 * spacing => TablePoint { left: slope(&value, &minus, step), right: slope(&plus, &value, step), value },
                    _ => {
                        let central = slope(&plus, &minus, 2.0 * step);
                        TablePoint { value, left: central.clone(), right: central }
                    }
                })
            })
            .collect();
        ContributionTable { start, spacing, points }
    }

    pub fn end(&self) -> f64 {
        self.start + self.spacing * (self.points.len() - 1) as f64
    }

    /// The cubic Hermite interpolant's value and slope at s for each of `trials` into `value`
    /// and `slope`; false outside the table or next to a missing point.
    pub fn interpolate(&self, s: f64, trials: &[usize], value: &mut [f64], slope: &mut [f64]) -> bool {
        let u = (s - self.start) / self.spacing;
        if !(u >= 0.0 && u <= (self.points.len() - 1) as f64) {
            return false;
        }
        let i = (u.floor() as usize).min(self.points.len().saturating_sub(2));
        let (Some(p0), Some(p1)) = (&self.points[i], &self.points[(i + 1).min(self.points.len() - 1)]) else { return false };
        let (c0, d0, c1, d1) = (&p0.value, &p0.right, &p1.value, &p1.left);
        let (t, h) = (u - i as f64, self.spacing);
        let (t2, t3) = (t * t, t * t * t);
        let (h00, h10, h01, h11) = (2.0 * t3 - 3.0 * t2 + 1.0, t3 - 2.0 * t2 + t, -2.0 * t3 + 3.0 * t2, t3 - t2);
        let (g00, g10, g01, g11) = (6.0 * t2 - 6.0 * t, 3.0 * t2 - 4.0 * t + 1.0, -6.0 * t2 + 6.0 * t, 3.0 * t2 - 2.0 * t);
        for (j, &k) in trials.iter().enumerate() {
            value[j] = h00 * c0[k] + h10 * h * d0[k] + h01 * c1[k] + h11 * h * d1[k];
            slope[j] = (g00 * c0[k] + g01 * c1[k]) / h + g10 * d0[k] + g11 * d1[k];
        }
        true
    }
}

/// Muscles fitted together and the trials that score them.
#[derive(Debug, Clone)]
pub struct MuscleGroup {
    /// Estimated-muscle indices.
    pub muscles: Vec<usize>,
    /// Trial indices.
    pub trials: Vec<usize>,
}

/// The groups: the estimated muscles with an activation in a direction's trials (the first
/// such direction) are fitted on those trials; any other estimated muscle alone, on all.
pub fn muscle_groups(model: &KneeMomentModel) -> Vec<MuscleGroup> {
    let names: Vec<&str> = model.estimated_names().collect();
    let mut assigned = vec![false; names.len()];
    let mut groups = Vec::new();
    for direction in super::trials::Direction::BOTH {
        let trials: Vec<usize> = (0..model.trials().len()).filter(|&t| model.trials()[t].direction == direction).collect();
        let active = |e: usize| trials.iter().any(|&t| model.trials()[t].activation(names[e]).is_some());
        let muscles: Vec<usize> = (0..names.len()).filter(|&e| !assigned[e] && active(e)).collect();
        if muscles.is_empty() {
            continue;
        }
        muscles.iter().for_each(|&e| assigned[e] = true);
        groups.push(MuscleGroup { muscles, trials });
    }
    let all: Vec<usize> = (0..model.trials().len()).collect();
    groups.extend((0..names.len()).filter(|&e| !assigned[e]).map(|e| MuscleGroup { muscles: vec![e], trials: all.clone() }));
    groups
}

/// A Gaussian prior on the coordinates, s_e − centre_e ~ N(0, τ²): with moment noise σ it joins
/// the least squares as one residual weight·(s_e − centre_e) per muscle, weight = σ/τ (N·m).
/// Weight 0 is no prior.
#[derive(Debug, Clone, PartialEq)]
pub struct CoordinatePrior {
    pub centre: Vec<f64>,
    pub weight: f64,
}

impl CoordinatePrior {
    /// The prior residual of muscle e at s, N·m.
    pub fn residual(&self, e: usize, s: f64) -> f64 {
        self.weight * (s - self.centre[e])
    }
}

/// The surrogate least squares of all estimated muscles: their tables, M_fixed − M_meas per
/// trial, and the prior.
#[derive(Debug, Clone, Copy)]
pub struct Surrogate<'a> {
    pub tables: &'a [ContributionTable],
    pub residual_base: &'a [f64],
    pub prior: &'a CoordinatePrior,
}

/// A minimum on the surrogate: of one group (its muscles' s, cost on its trials and their
/// priors) or of all estimated muscles (cost on all trials and priors).
#[derive(Debug, Clone, PartialEq)]
pub struct SurrogateMinimum {
    /// Σ (M − M_meas)² plus the prior's squared residuals, N²·m².
    pub cost: f64,
    pub s: Vec<f64>,
}

/// The distinct minima of all estimated muscles together, best first (at most `keep`): passes
/// of [`one_pass`], the first held at `start` (s per estimated muscle), each next one at the
/// best minimum so far, until a pass improves the best cost by less than 0.1 %.
pub fn search(surrogate: &Surrogate, groups: &[MuscleGroup], start: Vec<f64>, lattice_budget: f64, keep: usize) -> Vec<SurrogateMinimum> {
    let mut all: Vec<SurrogateMinimum> = Vec::new();
    let mut start = start;
    for _ in 0..MAX_PASSES {
        let found = one_pass(surrogate, groups, start, lattice_budget, keep);
        let improved = found.first().is_some_and(|f| all.first().is_none_or(|b| f.cost < b.cost * (1.0 - 1e-3)));
        for minimum in found {
            offer(&mut all, minimum, keep);
        }
        match all.first() {
            Some(best) if improved => start = best.s.clone(),
            _ => break,
        }
    }
    all
}

/// The groups take turns from `start`, each fitted from every point of a lattice of
/// ⌊`lattice_budget`^(1/k)⌋ levels per muscle (k its muscles, at least 2) with the others at
/// the best so far; every combination of the groups' kept minima of every round then starts a
/// fit of all muscles on all trials, since the groups are coupled through the passive forces of
/// each direction's antagonists.
fn one_pass(surrogate: &Surrogate, groups: &[MuscleGroup], start: Vec<f64>, lattice_budget: f64, keep: usize) -> Vec<SurrogateMinimum> {
    let mut best = start;
    let mut seen: Vec<Vec<SurrogateMinimum>> = vec![Vec::new(); groups.len()];
    for _ in 0..MAX_ROUNDS {
        let mut changed = false;
        for (g, group) in groups.iter().enumerate() {
            let Some(base) = held_residuals(surrogate, group, &best) else { continue };
            let found = group_minima(surrogate, group, &base, lattice_budget, keep);
            if let Some(first) = found.first() {
                for (&e, &s) in group.muscles.iter().zip(&first.s) {
                    changed |= (best[e] - s).abs() > SAME_MINIMUM;
                    best[e] = s;
                }
            }
            for minimum in found {
                if !seen[g].iter().any(|m| same_point(&m.s, &minimum.s)) {
                    seen[g].push(minimum);
                }
            }
        }
        if !changed {
            break;
        }
    }
    joint_minima(surrogate, groups, &best, &seen, keep)
}

/// Every combination of the groups' minima (others at `best`) refined on all trials together.
fn joint_minima(surrogate: &Surrogate, groups: &[MuscleGroup], best: &[f64], seen: &[Vec<SurrogateMinimum>], keep: usize) -> Vec<SurrogateMinimum> {
    let all = MuscleGroup { muscles: (0..surrogate.tables.len()).collect(), trials: (0..surrogate.residual_base.len()).collect() };
    let [lower, upper] = table_bounds(surrogate.tables, &all.muscles);
    let mut problem = SurrogateProblem::new(surrogate, &all, surrogate.residual_base);
    let mut minima = Vec::new();
    let combinations: usize = seen.iter().map(|g| g.len().max(1)).product();
    for n in 0..combinations {
        let mut x = best.to_vec();
        let mut stride = 1;
        for (group, kept) in groups.iter().zip(seen).filter(|(_, kept)| !kept.is_empty()) {
            let minimum = &kept[(n / stride) % kept.len()];
            group.muscles.iter().zip(&minimum.s).for_each(|(&e, &s)| x[e] = s);
            stride *= kept.len();
        }
        if let Some(cost) = problem.minimize(&mut x, &lower, &upper) {
            offer(&mut minima, SurrogateMinimum { cost, s: x }, keep);
        }
    }
    minima
}

fn same_point(a: &[f64], b: &[f64]) -> bool {
    a.iter().zip(b).all(|(a, b)| (a - b).abs() < SAME_MINIMUM)
}

/// M_fixed − M_meas plus the surrogate contributions of the muscles outside `group` at `s`,
/// per group trial.
fn held_residuals(surrogate: &Surrogate, group: &MuscleGroup, s: &[f64]) -> Option<Vec<f64>> {
    let tables = surrogate.tables;
    let mut base: Vec<f64> = group.trials.iter().map(|&t| surrogate.residual_base[t]).collect();
    let (mut value, mut slope) = (vec![0.0; base.len()], vec![0.0; base.len()]);
    for e in (0..tables.len()).filter(|e| !group.muscles.contains(e)) {
        if !tables[e].interpolate(s[e], &group.trials, &mut value, &mut slope) {
            return None;
        }
        base.iter_mut().zip(&value).for_each(|(b, v)| *b += v);
    }
    Some(base)
}

/// The group's distinct surrogate minima from every lattice start, best first; `base` is its
/// trials' residuals with the other groups held.
fn group_minima(surrogate: &Surrogate, group: &MuscleGroup, base: &[f64], lattice_budget: f64, keep: usize) -> Vec<SurrogateMinimum> {
    let k = group.muscles.len();
    let levels = (lattice_budget.powf(1.0 / k as f64).floor() as usize).max(2);
    let [lower, upper] = table_bounds(surrogate.tables, &group.muscles);
    let mut problem = SurrogateProblem::new(surrogate, group, base);
    let mut minima: Vec<SurrogateMinimum> = Vec::new();
    for n in 0..levels.pow(k as u32) {
        let mut x: Vec<f64> = (0..k).map(|j| lower[j] + (upper[j] - lower[j]) * (((n / levels.pow(j as u32)) % levels) as f64 + 0.5) / levels as f64).collect();
        if let Some(cost) = problem.minimize(&mut x, &lower, &upper) {
            offer(&mut minima, SurrogateMinimum { cost, s: x }, keep);
        }
    }
    minima
}

/// The tables' first and last s of `muscles`.
fn table_bounds(tables: &[ContributionTable], muscles: &[usize]) -> [Vec<f64>; 2] {
    [muscles.iter().map(|&e| tables[e].start).collect(), muscles.iter().map(|&e| tables[e].end()).collect()]
}

/// Keeps `candidate` among the best `keep` distinct minima, sorted by cost.
fn offer(minima: &mut Vec<SurrogateMinimum>, candidate: SurrogateMinimum, keep: usize) {
    let same = |m: &SurrogateMinimum| same_point(&m.s, &candidate.s);
    if minima.iter().any(|m| same(m) && m.cost <= candidate.cost) {
        return;
    }
    minima.retain(|m| !same(m));
    let at = minima.partition_point(|m| m.cost <= candidate.cost);
    minima.insert(at, candidate);
    minima.truncate(keep.max(1));
}

/// One group's residuals on the surrogate: base + Σ_group c_j(s_j) per group trial, then the
/// prior's residual per group muscle.
struct SurrogateProblem<'a> {
    tables: &'a [ContributionTable],
    prior: &'a CoordinatePrior,
    group: &'a MuscleGroup,
    base: &'a [f64],
    value: Vec<f64>,
    slope: Vec<f64>,
    residuals: DVector<f64>,
    jacobian: DMatrix<f64>,
}

impl<'a> SurrogateProblem<'a> {
    fn new(surrogate: &Surrogate<'a>, group: &'a MuscleGroup, base: &'a [f64]) -> SurrogateProblem<'a> {
        let (m, k) = (base.len(), group.muscles.len());
        let mut jacobian = DMatrix::zeros(m + k, k);
        (0..k).for_each(|j| jacobian[(m + j, j)] = surrogate.prior.weight);
        SurrogateProblem { tables: surrogate.tables, prior: surrogate.prior, group, base, value: vec![0.0; m], slope: vec![0.0; m], residuals: DVector::zeros(m + k), jacobian }
    }

    /// Residuals and Jacobian at x; Σ r² (N²·m²), `None` outside the surrogate.
    fn evaluate(&mut self, x: &[f64]) -> Option<f64> {
        let m = self.base.len();
        self.residuals.rows_mut(0, m).copy_from_slice(self.base);
        for (j, (&e, &s)) in self.group.muscles.iter().zip(x).enumerate() {
            if !self.tables[e].interpolate(s, &self.group.trials, &mut self.value, &mut self.slope) {
                return None;
            }
            self.residuals.iter_mut().zip(&self.value).for_each(|(r, v)| *r += v);
            self.residuals[m + j] = self.prior.residual(e, s);
            self.jacobian.view_mut((0, j), (m, 1)).copy_from_slice(&self.slope);
        }
        Some(self.residuals.norm_squared())
    }

    /// Projected Levenberg–Marquardt from x within [lower, upper]: the step clamped into the
    /// box, a variable at a bound that the gradient pushes outward held there. Stops when a
    /// step changes no s by more than [`SURROGATE_STEP_TOLERANCE`], or the damping exceeds
    /// 10¹⁰ (no descent left), or after [`SURROGATE_ITERATIONS`]. Returns Σ r² at x.
    fn minimize(&mut self, x: &mut [f64], lower: &[f64], upper: &[f64]) -> Option<f64> {
        let k = x.len();
        let mut cost = self.evaluate(x)?;
        let mut damping = 1e-6;
        let mut trial = x.to_vec();
        let (mut system, mut normal) = (DMatrix::zeros(k, k), DMatrix::zeros(k, k));
        let (mut step, mut gradient) = (DVector::zeros(k), DVector::zeros(k));
        for _ in 0..SURROGATE_ITERATIONS {
            // Trial evaluations overwrite J and r; the local model keeps those at x.
            self.jacobian.tr_mul_to(&self.residuals, &mut gradient);
            self.jacobian.tr_mul_to(&self.jacobian, &mut normal);
            let held = |j: usize| (x[j] <= lower[j] && gradient[j] > 0.0) || (x[j] >= upper[j] && gradient[j] < 0.0);
            loop {
                system.copy_from(&normal);
                for j in 0..k {
                    if held(j) {
                        system.row_mut(j).fill(0.0);
                        system.column_mut(j).fill(0.0);
                        system[(j, j)] = 1.0;
                        step[j] = 0.0;
                    } else {
                        system[(j, j)] += damping * normal[(j, j)].max(1e-12);
                        step[j] = -gradient[j];
                    }
                }
                let factor = Cholesky::new(system)?;
                factor.solve_mut(&mut step);
                system = factor.unpack();
                for j in 0..k {
                    trial[j] = (x[j] + step[j]).clamp(lower[j], upper[j]);
                }
                let moved = (0..k).map(|j| (trial[j] - x[j]).abs()).fold(0.0, f64::max);
                match self.evaluate(&trial) {
                    Some(trial_cost) if trial_cost < cost => {
                        x.copy_from_slice(&trial);
                        cost = trial_cost;
                        damping = (damping / 3.0).max(1e-12);
                        if moved <= SURROGATE_STEP_TOLERANCE {
                            return Some(cost);
                        }
                        break;
                    }
                    _ => {
                        damping *= 4.0;
                        if damping > 1e10 || moved <= SURROGATE_STEP_TOLERANCE {
                            return Some(cost);
                        }
                    }
                }
            }
        }
        Some(cost)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// c(s) = s³ − s tabulated with exact slopes: the Hermite interpolant reproduces cubics.
    #[test]
    fn hermite_interpolation_is_exact_for_cubics() {
        let f = |s: f64| s * s * s - s;
        let df = |s: f64| 3.0 * s * s - 1.0;
        let point = |s: f64| Some(TablePoint { value: vec![f(s)], left: vec![df(s)], right: vec![df(s)] });
        let table = ContributionTable { start: -1.0, spacing: 0.5, points: (0..5).map(|i| point(-1.0 + 0.5 * i as f64)).collect() };
        let (mut value, mut slope) = ([0.0], [0.0]);
        for s in [-1.0, -0.7, 0.1, 0.99, 1.0] {
            assert!(table.interpolate(s, &[0], &mut value, &mut slope));
            assert!((value[0] - f(s)).abs() < 1e-14 && (slope[0] - df(s)).abs() < 1e-13, "{s}");
        }
        assert!(!table.interpolate(1.01, &[0], &mut value, &mut slope));
    }

    /// Two minima of (c(s) − 0)² with c = (s² − 1)(s − 0.2): the lattice finds all three roots
    /// as distinct zero-cost minima.
    #[test]
    fn lattice_finds_distinct_minima() {
        let f = |s: f64| (s * s - 1.0) * (s - 0.2);
        let df = |s: f64| 3.0 * s * s - 0.4 * s - 1.0;
        let grid = |i: usize| -2.0 + 0.05 * i as f64;
        let table = ContributionTable { start: -2.0, spacing: 0.05, points: (0..81).map(|i| Some(TablePoint { value: vec![f(grid(i))], left: vec![df(grid(i))], right: vec![df(grid(i))] })).collect() };
        let group = MuscleGroup { muscles: vec![0], trials: vec![0] };
        let no_prior = CoordinatePrior { centre: vec![0.0], weight: 0.0 };
        let surrogate = Surrogate { tables: &[table], residual_base: &[0.0], prior: &no_prior };
        let minima = group_minima(&surrogate, &group, &[0.0], 12.0, 5);
        let mut roots: Vec<f64> = minima.iter().filter(|m| m.cost < 1e-12).map(|m| m.s[0]).collect();
        roots.sort_by(f64::total_cmp);
        assert_eq!(roots.len(), 3, "{minima:?}");
        for (root, expected) in roots.iter().zip([-1.0, 0.2, 1.0]) {
            assert!((root - expected).abs() < 1e-4, "{root}");
        }
    }
}
