//! Coefficients of OpenSim's `GCVSpline`: Woltring's GCVSPL (1986) as Simbody's
//! `SplineFitter` runs it (`SimTKmath/Geometry/src/gcvspl.cpp`, an f2c translation).
//!
//! GCVSPL fits a natural spline of degree 2m − 1 with knots at the data abscissae by
//! minimising  Σ (y_i − s(x_i))² + p·∫ (s⁽ᵐ⁾)²  over s; with B the banded matrix of
//! basis-function values at the knots and W the banded penalty matrix, the coefficients c
//! solve (B + p·W) c = y. The smoothing parameter p is searched (halving, doubling, then
//! golden section) to minimise a criterion of the residual mean square R and the normalised
//! trace τ = p·tr(W (B + p·W)⁻¹)/n: R − σ²(2τ − 1) for a given error variance σ² (σ² = 0
//! drives p to its lower clamp: interpolation), or R/τ² for generalized cross-validation.
//!
//! Band loops keep GCVSPL's 1-based indices and operation order, so the coefficients agree
//! with Simbody's to the bit; unit weights (Simbody passes 1) are left out.

use std::ops::{Index, IndexMut};

/// How GCVSpline chooses its smoothing, from its `error_variance` property.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Smoothing {
    /// Residual mean square matching this error variance; 0 (OpenSim's default) interpolates.
    ErrorVariance(f64),
    /// Generalized cross-validation (a negative `error_variance`).
    CrossValidation,
}

impl Smoothing {
    /// OpenSim's `GCVSpline::createSimTKFunction`: `fitFromGCV` when the variance is
    /// negative, else `fitFromErrorVariance`.
    pub(super) fn from_error_variance(error_variance: f64) -> Smoothing {
        if error_variance < 0.0 {
            Smoothing::CrossValidation
        } else {
            Smoothing::ErrorVariance(error_variance)
        }
    }
}

/// Lower bound on p·ē (GCVSPL's `EPS`), ē being the mean |W| entry over the mean |B| entry.
const EPSILON: f64 = 1e-15;
/// The golden ratio as GCVSPL writes it.
const GOLDEN: f64 = 1.618033983;
/// p at which the doubling search gives up: GCVSPL's 1/EPS as gcvspl.cpp writes it
/// (`999999999999999.88`, the same double).
const LARGEST_P: f64 = 999_999_999_999_999.9;

/// Natural-spline coefficients c_1…c_n of half order m (degree 2m − 1) for data (x, y),
/// n ≥ 2m, x strictly increasing.
pub(super) fn fit(half_order: usize, x: &[f64], y: &[f64], smoothing: Smoothing) -> Vec<f64> {
    let system = System::new(half_order, x, y, smoothing);
    system.solve(system.smoothing_parameter()).coefficients
}

/// A banded matrix with `width` diagonals on each side; `band[(i, k)]` is entry (i, i + k)
/// with 1-based row i.
#[derive(Debug, Clone)]
struct Band {
    width: isize,
    entries: Vec<f64>,
}

impl Band {
    fn zeros(width: isize, rows: usize) -> Band {
        Band { width, entries: vec![0.0; rows * (2 * width as usize + 1)] }
    }

    fn offset(&self, (row, k): (isize, isize)) -> usize {
        ((row - 1) * (2 * self.width + 1) + k + self.width) as usize
    }
}

impl Index<(isize, isize)> for Band {
    type Output = f64;
    fn index(&self, at: (isize, isize)) -> &f64 {
        &self.entries[self.offset(at)]
    }
}

impl IndexMut<(isize, isize)> for Band {
    fn index_mut(&mut self, at: (isize, isize)) -> &mut f64 {
        let offset = self.offset(at);
        &mut self.entries[offset]
    }
}

/// The data and the p-independent matrices of one fit.
struct System<'a> {
    m: isize,
    y: &'a [f64],
    smoothing: Smoothing,
    /// B: basis functions at the knots, half-bandwidth m − 1.
    basis: Band,
    /// W: penalty (divided-difference weights), half-bandwidth m.
    penalty: Band,
    /// ē = mean |W| / mean |B|; p·ē is the relative smoothing.
    scale: f64,
}

/// One solve of (B + p·W) c = y.
struct Solution {
    coefficients: Vec<f64>,
    /// The criterion being minimised over p.
    criterion: f64,
    /// p actually used: 0 when clamped from below, the clamp when clamped from above.
    effective_p: f64,
    /// Whether p was clamped from above (p·ē·EPS > 1).
    at_ceiling: bool,
}

impl<'a> System<'a> {
    fn new(half_order: usize, x: &[f64], y: &'a [f64], smoothing: Smoothing) -> System<'a> {
        let m = half_order as isize;
        let (basis, basis_mean) = basis(m, x);
        let (penalty, penalty_mean) = penalty(m, x);
        System { m, y, smoothing, basis, penalty, scale: penalty_mean / basis_mean }
    }

    fn n(&self) -> isize {
        self.y.len() as isize
    }

    /// GCVSPL's search for p: from p = 1/ē halve while the criterion falls, then double
    /// while it falls, then golden-section search the bracket to a relative 1e-6.
    fn smoothing_parameter(&self) -> f64 {
        let criterion = |p: f64| self.solve(p).criterion;
        let mut low = 1.0 / self.scale;
        let mut high = low * 2.0;
        let mut at_high = criterion(high);
        loop {
            let solution = self.solve(low);
            if solution.criterion > at_high {
                break;
            }
            if solution.effective_p <= 0.0 {
                return low;
            }
            (high, at_high) = (low, solution.criterion);
            low /= 2.0;
        }
        let mut upper = high * 2.0;
        let mut at_upper;
        loop {
            let solution = self.solve(upper);
            at_upper = solution.criterion;
            if at_upper > at_high {
                break;
            }
            // GCVSPL stops at p ≥ 1/EPS; once p·ē·EPS > 1 is clamped, every further doubling
            // repeats this solve and Simbody loops forever, so we stop there too.
            if solution.effective_p >= LARGEST_P || solution.at_ceiling {
                return low;
            }
            at_high = at_upper;
            upper *= 2.0;
        }
        high = upper;
        let mut step = (high - low) / GOLDEN;
        let (mut inner_high, mut inner_low) = (high - step, low + step);
        let (mut at_inner_high, mut at_inner_low) = (criterion(inner_high), criterion(inner_low));
        let converged = |low: f64, high: f64| {
            let relative = (high - low) / (low + high);
            relative * relative + 1.0 == 1.0 || relative <= 1e-6
        };
        loop {
            if at_inner_high <= at_inner_low {
                high = inner_low;
                if converged(low, high) {
                    break;
                }
                (inner_low, at_inner_low) = (inner_high, at_inner_high);
                step /= GOLDEN;
                inner_high = high - step;
                at_inner_high = criterion(inner_high);
            } else {
                low = inner_high;
                if converged(low, high) {
                    break;
                }
                (inner_high, at_inner_high) = (inner_low, at_inner_low);
                step /= GOLDEN;
                inner_low = low + step;
                at_inner_low = criterion(inner_low);
            }
        }
        (low + high) / 2.0
    }

    /// GCVSPL's `SPLC`: factorises B + p·W, solves for c, and evaluates the criterion from
    /// the residual mean square R and the normalised trace τ = p·tr(W (B + p·W)⁻¹)/n.
    fn solve(&self, p: f64) -> Solution {
        let (m, n) = (self.m, self.n());
        let (mut used_p, mut effective_p) = (p, p);
        let relative = p * self.scale;
        if relative < EPSILON {
            used_p = EPSILON / self.scale;
            effective_p = 0.0;
        }
        let at_ceiling = relative * EPSILON > 1.0;
        if at_ceiling {
            used_p = 1.0 / (self.scale * EPSILON);
            effective_p = used_p;
        }
        let mut system = Band::zeros(m, n as usize);
        for i in 1..=n {
            for k in -m.min(i - 1)..=m.min(n - i) {
                let smoothing = used_p * self.penalty[(i, k)];
                system[(i, k)] = if k.abs() == m { smoothing } else { self.basis[(i, k)] + smoothing };
            }
        }
        factorize(&mut system);
        let coefficients = substitute(&system, self.y);
        let trace = penalty_trace(&self.penalty, &mut system) * used_p / n as f64;
        let residual = self.residual_mean_square(&coefficients);
        let criterion = match self.smoothing {
            Smoothing::ErrorVariance(variance) => residual - variance * (trace * 2.0 - 1.0),
            Smoothing::CrossValidation => residual / trace / trace,
        };
        Solution { coefficients, criterion, effective_p, at_ceiling }
    }

    /// Σ (B c − y)_i² / n.
    fn residual_mean_square(&self, c: &[f64]) -> f64 {
        let (m, n) = (self.m, self.n());
        let mut sum = 0.0;
        for i in 1..=n {
            let mut residual = -self.y[(i - 1) as usize];
            for k in -(m - 1).min(i - 1)..=(m - 1).min(n - i) {
                residual += self.basis[(i, k)] * c[(i + k - 1) as usize];
            }
            sum += residual * residual;
        }
        sum / n as f64
    }
}

/// GCVSPL's `BASIS`: values of the 2m-th order B-spline-like basis at each knot (band of
/// half-width m − 1, rows beyond the data zeroed) and the mean absolute entry.
fn basis(m: isize, x: &[f64]) -> (Band, f64) {
    let n = x.len() as isize;
    let mut b = Band::zeros(m - 1, n as usize);
    if m == 1 {
        b.entries.fill(1.0);
        return (b, 1.0);
    }
    let knot = |j: isize| x[(j - 1) as usize];
    let (mm1, m2) = (m - 1, 2 * m);
    // q[j] for j in −(m − 1)..=m, stored at j + m − 1.
    let slot = |j: isize| (j + mm1) as usize;
    let mut q = vec![0.0; 2 * m as usize];
    for l in 1..=n {
        q.fill(0.0);
        q[slot(mm1)] = if l != 1 && l != n { 1.0 / (knot(l + 1) - knot(l - 1)) } else { 1.0 };
        let at = knot(l);
        for i in 3..=m2 {
            let mut ir = m + 1 - i;
            let mut v = q[slot(ir)];
            for j in l + 1..=i {
                let u = v;
                v = q[slot(ir + 1)];
                q[slot(ir)] = u + (knot(j) - at) * v;
                ir += 1;
            }
            for j in (l - i + 1).max(1)..=(l - 1).min(n - i) {
                let u = v;
                v = q[slot(ir + 1)];
                q[slot(ir)] = if i < m2 {
                    let y = knot(i + j);
                    u + (v - u) * (y - at) / (y - knot(j))
                } else {
                    (at - knot(j)) * u + (knot(i + j) - at) * v
                };
                ir += 1;
            }
            for j in n - i + 1..l {
                let u = v;
                v = q[slot(ir + 1)];
                q[slot(ir)] = (at - knot(j)) * u + v;
                ir += 1;
            }
        }
        for j in -mm1..=mm1 {
            b[(l, j)] = q[slot(j)];
        }
    }
    for i in 1..=mm1 {
        for k in i..=mm1 {
            b[(i, -k)] = 0.0;
            b[(n + 1 - i, k)] = 0.0;
        }
    }
    let mean = b.entries.iter().fold(0.0, |sum, v| sum + v.abs()) / n as f64;
    (b, mean)
}

/// GCVSPL's `PREP`: the penalty band W, column by column the m-th divided-difference
/// weights over the 2m + 1 knots around each datum (scaled by (2m − 1)!/(m − 1)!-type
/// factors and the local span), and its mean absolute entry. Writes the band storage in
/// GCVSPL's flat order (`flat[jj − 1]`, stepping 2m down a column).
fn penalty(m: isize, x: &[f64]) -> (Band, f64) {
    let n = x.len() as isize;
    let knot = |j: isize| x[(j - 1) as usize];
    let (m2, width) = (2 * m, 2 * m + 1);
    let mut we = Band::zeros(m, n as usize);
    let flat = |jj: isize| (jj - 1) as usize;
    let mut factor = -1.0;
    for i in 2..=m {
        factor = -factor * i as f64;
    }
    for i in m + 1..m2 {
        factor *= i as f64;
    }
    let (mut first, mut last, mut column_start) = (1, m, m + 1);
    for j in 1..=n {
        let mut step = width;
        let f = if j > n - m {
            factor = -factor;
            factor
        } else if j < m + 1 {
            step = 1;
            factor
        } else {
            factor * (knot(j + m) - knot(j - m))
        };
        if j > m + 1 {
            first += 1;
        }
        if last < n {
            last += 1;
        }
        let mut jj = column_start;
        for l in first..=last {
            let mut weight = f;
            for i in (first..=last).filter(|&i| i != l) {
                weight /= knot(l) - knot(i);
            }
            we.entries[flat(jj)] = weight;
            jj += m2;
        }
        column_start += step;
    }
    let (mut corner, end) = (1, width * n + 1);
    for i in 1..=m {
        for k in corner..=corner + m - i {
            we.entries[flat(k)] = 0.0;
            we.entries[flat(end - k)] = 0.0;
        }
        corner += width;
    }
    let mean = we.entries.iter().fold(0.0, |sum, v| sum + v.abs()) / n as f64;
    (we, mean)
}

/// GCVSPL's `BANDET`: in-place LU factorisation (no pivoting) of a band matrix.
fn factorize(e: &mut Band) {
    let (m, n) = (e.width, (e.entries.len() / (2 * e.width as usize + 1)) as isize);
    for i in 1..=n {
        let mut di = e[(i, 0)];
        let mi = m.min(i - 1);
        if mi >= 1 {
            for k in 1..=mi {
                di -= e[(i, -k)] * e[(i - k, k)];
            }
            e[(i, 0)] = di;
        }
        for l in 1..=m.min(n - i) {
            let mut dl = e[(i + l, -l)];
            let km = (m - l).min(i - 1);
            if km >= 1 {
                let mut du = e[(i, l)];
                for k in 1..=km {
                    du -= e[(i, -k)] * e[(i - k, l + k)];
                    dl -= e[(l + i, -l - k)] * e[(i - k, k)];
                }
                e[(i, l)] = du;
            }
            e[(i + l, -l)] = dl / di;
        }
    }
}

/// GCVSPL's `BANSOL`: forward and back substitution with the factors from [`factorize`].
fn substitute(e: &Band, y: &[f64]) -> Vec<f64> {
    let (m, n) = (e.width, y.len() as isize);
    let mut c = vec![0.0; y.len()];
    let at = |i: isize| (i - 1) as usize;
    c[0] = y[0];
    for i in 2..=n {
        let mut d = y[at(i)];
        for l in 1..=m.min(i - 1) {
            d -= e[(i, -l)] * c[at(i - l)];
        }
        c[at(i)] = d;
    }
    c[at(n)] /= e[(n, 0)];
    for i in (1..n).rev() {
        let mut d = c[at(i)];
        for l in 1..=m.min(n - i) {
            d -= e[(i, l)] * c[at(i + l)];
        }
        c[at(i)] = d / e[(i, 0)];
    }
    c
}

/// GCVSPL's `TRINV`: overwrites the factors in `e` with the central band of (B + p·W)⁻¹
/// and returns tr(W (B + p·W)⁻¹).
fn penalty_trace(w: &Band, e: &mut Band) -> f64 {
    let (m, n) = (e.width, (e.entries.len() / (2 * e.width as usize + 1)) as isize);
    // GCVSPL keeps these two rows in unused corners of `e`; index k − 1 holds k = 1…m.
    let mut upper = vec![0.0; m as usize];
    let mut lower = vec![0.0; m as usize];
    e[(n, 0)] = 1.0 / e[(n, 0)];
    for i in (1..n).rev() {
        let mi = m.min(n - i);
        let mut dd = 1.0 / e[(i, 0)];
        for k in 1..=mi {
            upper[(k - 1) as usize] = e[(i, k)] * dd;
            lower[(k - 1) as usize] = e[(k + i, -k)];
        }
        dd += dd;
        for j in (1..=mi).rev() {
            let (mut du, mut dl) = (0.0, 0.0);
            for k in 1..=mi {
                du -= upper[(k - 1) as usize] * e[(i + k, j - k)];
                dl -= lower[(k - 1) as usize] * e[(i + j, k - j)];
            }
            e[(i, j)] = du;
            e[(j + i, -j)] = dl;
            dd -= upper[(j - 1) as usize] * dl + lower[(j - 1) as usize] * du;
        }
        e[(i, 0)] = dd / 2.0;
    }
    let mut trace = 0.0;
    for i in 1..=n {
        for k in -m.min(i - 1)..=m.min(n - i) {
            trace += w[(i, k)] * e[(k + i, -k)];
        }
    }
    trace
}
