//! The global search of the rest-curve fit. On its rest curve each estimated muscle has one
//! coordinate s, and the knee moment is a sum of per-muscle contributions,
//! M_t = M_fixed,t + Σ_j c_j(s_j, t). So each muscle's c_j(·, t) is tabulated once, with its
//! slope, on a uniform grid of s, and interpolated by cubic Hermite pieces: a surrogate
//! whose evaluation costs no equilibrium. The moment error on it has many small basins: five
//! angles per direction give ten residuals for eight unknowns, and each direction's agonists
//! are coupled to the other direction's trials through their passive forces, so the truth is
//! found only by fits that move all muscles together from starts near it. Two sources of starts:
//! - pairing: the muscles split in two halves (one direction's agonists and the rest); every
//!   combination of grid nodes in each half is summed once, and the pairs of combinations with
//!   the smallest cost start fits (a meet-in-the-middle scan of a grid too large to fit from);
//! - the groups' lattices: each group's s from every point of a coarse lattice, the other
//!   muscles at the best minimum so far, in rounds.
//!
//! Every start gets a short screening fit; the best screened minima are polished, and the
//! distinct minima found, best first, are the starts of the exact refinement.

use super::knee_moment::{EstimatedMuscles, KneeMomentModel};
use super::rest_curve::RestCurve;
use nalgebra::{Cholesky, DMatrix, DVector};

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
/// the start of the rest curve's clamped branch, where the curve has a corner), and the curve
/// point's [L_opt, L_ts], m.
#[derive(Debug, Clone)]
pub struct TablePoint {
    pub value: Vec<f64>,
    pub left: Vec<f64>,
    pub right: Vec<f64>,
    pub lengths: [f64; 2],
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
                    curve.contributions(model, workspace, s, &mut hint, &mut out).map(|p| (out, [p.optimal_fiber_length, p.tendon_slack_length]))
                };
                let ((value, lengths), (plus, _), (minus, _)) = (at(s)?, at(s + step)?, at(s - step)?);
                let slope = |a: &[f64], b: &[f64], h: f64| -> Vec<f64> { a.iter().zip(b).map(|(a, b)| (a - b) / h).collect() };
                Some(match corner {
                    Some(corner) if (s - corner).abs() < 1e-9 * spacing => TablePoint { left: slope(&value, &minus, step), right: slope(&plus, &value, step), value, lengths },
                    _ => {
                        let central = slope(&plus, &minus, 2.0 * step);
                        TablePoint { value, left: central.clone(), right: central, lengths }
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
        let Some((p0, p1, t)) = self.interval(s) else { return false };
        let (c0, d0, c1, d1) = (&p0.value, &p0.right, &p1.value, &p1.left);
        let h = self.spacing;
        let (t2, t3) = (t * t, t * t * t);
        let (h00, h10, h01, h11) = (2.0 * t3 - 3.0 * t2 + 1.0, t3 - 2.0 * t2 + t, -2.0 * t3 + 3.0 * t2, t3 - t2);
        let (g00, g10, g01, g11) = (6.0 * t2 - 6.0 * t, 3.0 * t2 - 4.0 * t + 1.0, -6.0 * t2 + 6.0 * t, 3.0 * t2 - 2.0 * t);
        for (j, &k) in trials.iter().enumerate() {
            value[j] = h00 * c0[k] + h10 * h * d0[k] + h01 * c1[k] + h11 * h * d1[k];
            slope[j] = (g00 * c0[k] + g01 * c1[k]) / h + g10 * d0[k] + g11 * d1[k];
        }
        true
    }

    /// The curve's [L_opt, L_ts] at s, m, interpolated linearly; `None` where
    /// [`Self::interpolate`] is false.
    pub fn lengths(&self, s: f64) -> Option<[f64; 2]> {
        let (p0, p1, t) = self.interval(s)?;
        Some([0, 1].map(|k| (1.0 - t) * p0.lengths[k] + t * p1.lengths[k]))
    }

    /// The table points around s and s's position between them in [0, 1]; `None` outside the
    /// table or next to a missing point.
    fn interval(&self, s: f64) -> Option<(&TablePoint, &TablePoint, f64)> {
        let u = (s - self.start) / self.spacing;
        if !(u >= 0.0 && u <= (self.points.len() - 1) as f64) {
            return None;
        }
        let i = (u.floor() as usize).min(self.points.len().saturating_sub(2));
        let (Some(p0), Some(p1)) = (&self.points[i], &self.points[(i + 1).min(self.points.len() - 1)]) else { return None };
        Some((p0, p1, u - i as f64))
    }
}

/// The groups, as estimated-muscle indices: the muscles with an activation in a direction's
/// trials (the first such direction), one group per direction; any other muscle alone.
pub fn muscle_groups(model: &KneeMomentModel) -> Vec<Vec<usize>> {
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
        groups.push(muscles);
    }
    groups.extend((0..names.len()).filter(|&e| !assigned[e]).map(|e| vec![e]));
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

/// A minimum of all estimated muscles on the surrogate.
#[derive(Debug, Clone, PartialEq)]
pub struct SurrogateMinimum {
    /// Σ (M − M_meas)² plus the prior's squared residuals, N²·m².
    pub cost: f64,
    pub s: Vec<f64>,
}

/// How widely `search` looks.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SearchBudget {
    /// Grid combinations per half in the pairing: k muscles get ⌊pairing^(1/k)⌋ nodes each.
    pub pairing: f64,
    /// Best pairs of combinations fitted from.
    pub pair_starts: usize,
    /// Lattice starts per group: k muscles get ⌊lattice^(1/k)⌋ levels each.
    pub lattice: f64,
    /// The same for the coarser lattice held at each runner-up minimum.
    pub runner_up_lattice: f64,
    /// Distinct minima returned.
    pub keep: usize,
}

impl Default for SearchBudget {
    fn default() -> Self {
        SearchBudget { pairing: 2401.0, pair_starts: 256, lattice: 625.0, runner_up_lattice: 81.0, keep: 4 }
    }
}

/// Minima closer than this in every s are one.
const SAME_MINIMUM: f64 = 1e-3;
/// The largest change of any s in one Levenberg–Marquardt step (about 10 % of L_opt): the
/// Gauss–Newton steps of ten residuals in eight unknowns are long and jump between basins.
const MAX_STEP: f64 = 0.1;
/// The short fit from every start, and the polish of the screened minima kept.
const SCREEN: Stopping = Stopping { step_tolerance: 1e-6, iterations: 30 };
const POLISH: Stopping = Stopping { step_tolerance: 1e-10, iterations: 200 };
/// Screened minima kept per minimum returned.
const SCREENED_PER_KEPT: usize = 4;
/// Rounds of the groups' lattices.
const MAX_ROUNDS: usize = 4;

/// The distinct minima of all estimated muscles, best first (at most `budget.keep`). Screened
/// from: the pairing's starts and `start` (s per estimated muscle); the groups' lattices in
/// rounds, the first group first held at `start`, every other lattice at the best minimum so
/// far, until a round improves the best cost by less than 0.1 %; then each group's coarse
/// lattice held at each runner-up (a group already right there may complete it).
pub fn search(surrogate: &Surrogate, groups: &[Vec<usize>], start: &[f64], budget: &SearchBudget) -> Vec<SurrogateMinimum> {
    let mut problem = SurrogateProblem::new(*surrogate);
    let keep = budget.keep.max(1);
    let mut screened = Vec::new();
    let screen = |problem: &mut SurrogateProblem, screened: &mut Vec<SurrogateMinimum>, starts: Vec<Vec<f64>>| {
        for mut x in starts {
            if let Some(cost) = problem.minimize(&mut x, SCREEN) {
                offer(screened, SurrogateMinimum { cost, s: x }, SCREENED_PER_KEPT * keep);
            }
        }
    };
    let mut starts = pair_starts(surrogate, &halves(groups, surrogate.tables.len()), budget);
    starts.push(start.to_vec());
    screen(&mut problem, &mut screened, starts);
    let mut held = start.to_vec();
    for _ in 0..MAX_ROUNDS {
        let Some(before) = screened.first().map(|m| m.cost) else { break };
        for group in groups {
            let starts = problem.lattice(group, &held, budget.lattice);
            screen(&mut problem, &mut screened, starts);
            held = screened[0].s.clone();
        }
        if screened[0].cost >= before * (1.0 - 1e-3) {
            break;
        }
    }
    let runner_ups: Vec<Vec<f64>> = screened.iter().skip(1).take(keep).map(|m| m.s.clone()).collect();
    for held in &runner_ups {
        for group in groups {
            let starts = problem.lattice(group, held, budget.runner_up_lattice);
            screen(&mut problem, &mut screened, starts);
        }
    }
    let mut minima = Vec::new();
    for mut minimum in screened {
        if let Some(cost) = problem.minimize(&mut minimum.s, POLISH) {
            offer(&mut minima, SurrogateMinimum { cost, s: minimum.s }, keep);
        }
    }
    minima
}

/// The pairing's halves: the first group and the other muscles, or, when the first group
/// holds every muscle, its first and second half.
fn halves(groups: &[Vec<usize>], muscles: usize) -> [Vec<usize>; 2] {
    let first = groups.first().cloned().unwrap_or_default();
    if first.len() < muscles {
        return [first.clone(), (0..muscles).filter(|e| !first.contains(e)).collect()];
    }
    let (a, b) = first.split_at(muscles / 2);
    [a.to_vec(), b.to_vec()]
}

/// One half's combinations of grid nodes: per combination its muscles' s, their summed
/// contributions per trial (N·m) and their prior's squared residuals (N²·m²).
struct HalfGrid {
    s: Vec<Vec<f64>>,
    moments: Vec<Vec<f64>>,
    prior: Vec<f64>,
}

impl HalfGrid {
    /// ⌊budget^(1/k)⌋ nodes per muscle, at the cell centres of its table; combinations with a
    /// missing node are left out. An empty half has one empty combination.
    fn new(surrogate: &Surrogate, muscles: &[usize], budget: f64) -> HalfGrid {
        let levels = levels(budget, muscles.len());
        let mut grid = HalfGrid { s: Vec::new(), moments: Vec::new(), prior: Vec::new() };
        'combination: for n in 0..levels.pow(muscles.len() as u32) {
            let (mut s, mut moments, mut prior) = (Vec::with_capacity(muscles.len()), vec![0.0; surrogate.residual_base.len()], 0.0);
            for (j, &e) in muscles.iter().enumerate() {
                let table = &surrogate.tables[e];
                let node = (cell_centre(n, j, levels) * (table.points.len() - 1) as f64).round() as usize;
                let Some(point) = &table.points[node] else { continue 'combination };
                let x = table.start + table.spacing * node as f64;
                moments.iter_mut().zip(&point.value).for_each(|(m, v)| *m += v);
                prior += surrogate.prior.residual(e, x).powi(2);
                s.push(x);
            }
            grid.s.push(s);
            grid.moments.push(moments);
            grid.prior.push(prior);
        }
        grid
    }
}

/// The `budget.pair_starts` pairs of the halves' combinations with the smallest cost
/// Σ_t (M_fixed − M_meas + m_A + m_B)² + prior, as starts (s per estimated muscle).
fn pair_starts(surrogate: &Surrogate, halves: &[Vec<usize>; 2], budget: &SearchBudget) -> Vec<Vec<f64>> {
    let [a, b] = [0, 1].map(|h| HalfGrid::new(surrogate, &halves[h], budget.pairing));
    let keep = budget.pair_starts.max(1);
    let mut best: Vec<(f64, usize, usize)> = Vec::with_capacity(2 * keep);
    let mut bound = f64::INFINITY;
    for (i, moments_a) in a.moments.iter().enumerate() {
        let base: Vec<f64> = moments_a.iter().zip(surrogate.residual_base).map(|(m, r)| m + r).collect();
        for (j, moments_b) in b.moments.iter().enumerate() {
            let mut cost = a.prior[i] + b.prior[j];
            for (r, m) in base.iter().zip(moments_b) {
                cost += (r + m) * (r + m);
                if cost >= bound {
                    break;
                }
            }
            if cost < bound {
                best.push((cost, i, j));
                if best.len() == 2 * keep {
                    best.sort_by(|x, y| x.0.total_cmp(&y.0));
                    best.truncate(keep);
                    bound = best[keep - 1].0;
                }
            }
        }
    }
    best.sort_by(|x, y| x.0.total_cmp(&y.0));
    best.truncate(keep);
    let muscles = surrogate.tables.len();
    best.into_iter()
        .map(|(_, i, j)| {
            let mut s = vec![0.0; muscles];
            halves[0].iter().zip(&a.s[i]).chain(halves[1].iter().zip(&b.s[j])).for_each(|(&e, &x)| s[e] = x);
            s
        })
        .collect()
}

/// Levels per muscle when k muscles share `budget` points: ⌊budget^(1/k)⌋, at least 2.
fn levels(budget: f64, k: usize) -> usize {
    (budget.powf(1.0 / k.max(1) as f64).floor() as usize).max(2)
}

/// Of point n of a lattice with `levels` per muscle, muscle j's cell centre in [0, 1].
fn cell_centre(n: usize, j: usize, levels: usize) -> f64 {
    (((n / levels.pow(j as u32)) % levels) as f64 + 0.5) / levels as f64
}

fn same_point(a: &[f64], b: &[f64]) -> bool {
    a.iter().zip(b).all(|(a, b)| (a - b).abs() < SAME_MINIMUM)
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

/// When a Levenberg–Marquardt fit stops: a step changes no s by more than `step_tolerance`,
/// or after `iterations`.
#[derive(Debug, Clone, Copy)]
struct Stopping {
    step_tolerance: f64,
    iterations: usize,
}

/// The surrogate residuals of all estimated muscles: M_fixed − M_meas + Σ_e c_e(s_e) per trial,
/// then the prior's residual per muscle; s within the tables.
struct SurrogateProblem<'a> {
    surrogate: Surrogate<'a>,
    trials: Vec<usize>,
    lower: Vec<f64>,
    upper: Vec<f64>,
    value: Vec<f64>,
    slope: Vec<f64>,
    residuals: DVector<f64>,
    jacobian: DMatrix<f64>,
}

impl<'a> SurrogateProblem<'a> {
    fn new(surrogate: Surrogate<'a>) -> SurrogateProblem<'a> {
        let (m, k) = (surrogate.residual_base.len(), surrogate.tables.len());
        let mut jacobian = DMatrix::zeros(m + k, k);
        (0..k).for_each(|j| jacobian[(m + j, j)] = surrogate.prior.weight);
        SurrogateProblem {
            surrogate,
            trials: (0..m).collect(),
            lower: surrogate.tables.iter().map(|t| t.start).collect(),
            upper: surrogate.tables.iter().map(ContributionTable::end).collect(),
            value: vec![0.0; m],
            slope: vec![0.0; m],
            residuals: DVector::zeros(m + k),
            jacobian,
        }
    }

    /// Starts with `group`'s s at every point of a lattice of ⌊budget^(1/k)⌋ levels per muscle
    /// (cell centres of the table ranges) and the other muscles at `held`.
    fn lattice(&self, group: &[usize], held: &[f64], budget: f64) -> Vec<Vec<f64>> {
        let levels = levels(budget, group.len());
        (0..levels.pow(group.len() as u32))
            .map(|n| {
                let mut x = held.to_vec();
                group.iter().enumerate().for_each(|(j, &e)| x[e] = self.lower[e] + (self.upper[e] - self.lower[e]) * cell_centre(n, j, levels));
                x
            })
            .collect()
    }

    /// Residuals and Jacobian at x; Σ r² (N²·m²), `None` outside the surrogate.
    fn evaluate(&mut self, x: &[f64]) -> Option<f64> {
        let m = self.trials.len();
        self.residuals.rows_mut(0, m).copy_from_slice(self.surrogate.residual_base);
        for (e, &s) in x.iter().enumerate() {
            if !self.surrogate.tables[e].interpolate(s, &self.trials, &mut self.value, &mut self.slope) {
                return None;
            }
            self.residuals.iter_mut().zip(&self.value).for_each(|(r, v)| *r += v);
            self.residuals[m + e] = self.surrogate.prior.residual(e, s);
            self.jacobian.view_mut((0, e), (m, 1)).copy_from_slice(&self.slope);
        }
        Some(self.residuals.norm_squared())
    }

    /// Projected Levenberg–Marquardt from x within the tables: the step shortened to
    /// [`MAX_STEP`] and clamped into the box, a variable at a bound that the gradient pushes
    /// outward held there. Stops as `stopping` says, or when the damping exceeds 10¹⁰ (no
    /// descent left). Returns Σ r² at x.
    fn minimize(&mut self, x: &mut [f64], stopping: Stopping) -> Option<f64> {
        let k = x.len();
        let mut cost = self.evaluate(x)?;
        let mut damping = 1e-6;
        let mut trial = x.to_vec();
        let (mut system, mut normal) = (DMatrix::zeros(k, k), DMatrix::zeros(k, k));
        let (mut step, mut gradient) = (DVector::zeros(k), DVector::zeros(k));
        for _ in 0..stopping.iterations {
            // Trial evaluations overwrite J and r; the local model keeps those at x.
            self.jacobian.tr_mul_to(&self.residuals, &mut gradient);
            self.jacobian.tr_mul_to(&self.jacobian, &mut normal);
            loop {
                system.copy_from(&normal);
                for j in 0..k {
                    if (x[j] <= self.lower[j] && gradient[j] > 0.0) || (x[j] >= self.upper[j] && gradient[j] < 0.0) {
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
                let longest = step.amax();
                if longest > MAX_STEP {
                    step *= MAX_STEP / longest;
                }
                for j in 0..k {
                    trial[j] = (x[j] + step[j]).clamp(self.lower[j], self.upper[j]);
                }
                let moved = (0..k).map(|j| (trial[j] - x[j]).abs()).fold(0.0, f64::max);
                match self.evaluate(&trial) {
                    Some(trial_cost) if trial_cost < cost => {
                        x.copy_from_slice(&trial);
                        cost = trial_cost;
                        damping = (damping / 3.0).max(1e-12);
                        if moved <= stopping.step_tolerance {
                            return Some(cost);
                        }
                        break;
                    }
                    _ => {
                        damping *= 4.0;
                        if damping > 1e10 || moved <= stopping.step_tolerance {
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

    /// c(s) = s³ − s tabulated with exact slopes: the Hermite interpolant reproduces cubics; the
    /// lengths [1 + s, 2 − s] are linear and reproduced too.
    #[test]
    fn hermite_interpolation_is_exact_for_cubics() {
        let f = |s: f64| s * s * s - s;
        let df = |s: f64| 3.0 * s * s - 1.0;
        let point = |s: f64| Some(TablePoint { value: vec![f(s)], left: vec![df(s)], right: vec![df(s)], lengths: [1.0 + s, 2.0 - s] });
        let table = ContributionTable { start: -1.0, spacing: 0.5, points: (0..5).map(|i| point(-1.0 + 0.5 * i as f64)).collect() };
        let (mut value, mut slope) = ([0.0], [0.0]);
        for s in [-1.0, -0.7, 0.1, 0.99, 1.0] {
            assert!(table.interpolate(s, &[0], &mut value, &mut slope));
            assert!((value[0] - f(s)).abs() < 1e-14 && (slope[0] - df(s)).abs() < 1e-13, "{s}");
            let [optimal, slack] = table.lengths(s).unwrap();
            assert!((optimal - 1.0 - s).abs() < 1e-14 && (slack - 2.0 + s).abs() < 1e-14, "{s}");
        }
        assert!(!table.interpolate(1.01, &[0], &mut value, &mut slope));
        assert!(table.lengths(1.01).is_none());
    }

    /// A table of c(s) over [−2, 2] (81 points) with exact slopes dc/ds.
    fn table(c: impl Fn(f64) -> Vec<f64>, dc: impl Fn(f64) -> Vec<f64>) -> ContributionTable {
        let grid = |i: usize| -2.0 + 0.05 * i as f64;
        ContributionTable { start: -2.0, spacing: 0.05, points: (0..81).map(|i| Some(TablePoint { value: c(grid(i)), left: dc(grid(i)), right: dc(grid(i)), lengths: [0.0; 2] })).collect() }
    }

    /// (c(s) − 0)² with c = (s² − 1)(s − 0.2) has three zeros: the search returns all three as
    /// distinct zero-cost minima.
    #[test]
    fn search_finds_distinct_minima() {
        let tables = [table(|s| vec![(s * s - 1.0) * (s - 0.2)], |s| vec![3.0 * s * s - 0.4 * s - 1.0])];
        let no_prior = CoordinatePrior { centre: vec![0.0], weight: 0.0 };
        let surrogate = Surrogate { tables: &tables, residual_base: &[0.0], prior: &no_prior };
        let budget = SearchBudget { pairing: 2.0, pair_starts: 1, lattice: 12.0, runner_up_lattice: 2.0, keep: 5 };
        let minima = search(&surrogate, &[vec![0]], &[1.9], &budget);
        let mut roots: Vec<f64> = minima.iter().filter(|m| m.cost < 1e-12).map(|m| m.s[0]).collect();
        roots.sort_by(f64::total_cmp);
        assert_eq!(roots.len(), 3, "{minima:?}");
        for (root, expected) in roots.iter().zip([-1.0, 0.2, 1.0]) {
            assert!((root - expected).abs() < 1e-4, "{root}");
        }
    }

    /// Two coupled muscles, c₀(a) = (10a, 2a²) and c₁(b) = (3b², 10b), and moments made at
    /// a = 0.3, b = −0.5 (the only solution in the tables): the pairing's best start is the
    /// grid pair next to it, and the search's best minimum is the solution.
    #[test]
    fn pairing_starts_next_to_the_solution() {
        let tables = [table(|a| vec![10.0 * a, 2.0 * a * a], |a| vec![10.0, 4.0 * a]), table(|b| vec![3.0 * b * b, 10.0 * b], |b| vec![6.0 * b, 10.0])];
        let base = [-(3.0 + 0.75), -(0.18 - 5.0)];
        let no_prior = CoordinatePrior { centre: vec![0.0; 2], weight: 0.0 };
        let surrogate = Surrogate { tables: &tables, residual_base: &base, prior: &no_prior };
        let budget = SearchBudget { pairing: 81.0, pair_starts: 1, lattice: 2.0, runner_up_lattice: 2.0, keep: 1 };
        let starts = pair_starts(&surrogate, &halves(&[vec![0], vec![1]], 2), &budget);
        assert!((starts[0][0] - 0.3).abs() <= 0.05 + 1e-12 && (starts[0][1] + 0.5).abs() <= 0.05 + 1e-12, "{starts:?}");
        let minima = search(&surrogate, &[vec![0], vec![1]], &[-1.9, 1.9], &budget);
        assert!((minima[0].s[0] - 0.3).abs() < 1e-6 && (minima[0].s[1] + 0.5).abs() < 1e-6 && minima[0].cost < 1e-12, "{minima:?}");
    }
}
