//! OpenSim's `GCVSpline`, which OpenSim evaluates as a Simbody `Spline`: a natural spline of
//! odd degree 2m − 1 with knots at the data, evaluated by GCVSPL's `SPLDER`. Beyond the
//! knots it continues as the polynomial of degree m − 1 that natural end conditions give.

use super::gcv_fit::{fit, Smoothing};

/// Largest half order OpenSim allows (degree 7); OpenSim clamps the half order to 1…4.
const MAX_HALF_ORDER: usize = 4;

/// A fitted natural spline: knots x_1…x_n and GCVSPL coefficients c_1…c_n.
#[derive(Debug, Clone)]
pub(super) struct GcvSpline {
    /// m: the degree is 2m − 1.
    half_order: usize,
    x: Vec<f64>,
    coefficients: Vec<f64>,
    /// Buckets of equal width over [x_1, x_n], n of them, for `interval`.
    buckets: KnotBuckets,
}

/// Where the interval search starts: bucket b covers [x_1 + b·w, x_1 + (b + 1)·w) and
/// `first[b]` counts the knots below its lower edge.
#[derive(Debug, Clone)]
struct KnotBuckets {
    /// 1/w.
    per_width: f64,
    first: Vec<usize>,
}

/// Room for the 2m local coefficients, 1-based as in `SPLDER` (slot 0 unused).
type Window = [f64; 2 * MAX_HALF_ORDER + 1];

impl GcvSpline {
    /// Fits degree `degree` (odd, n ≥ degree + 1 points) as `GCVSpline::createSimTKFunction`.
    pub(super) fn new(degree: usize, x: &[f64], y: &[f64], smoothing: Smoothing) -> GcvSpline {
        let half_order = degree.div_ceil(2).clamp(1, MAX_HALF_ORDER);
        let buckets = KnotBuckets::new(x);
        GcvSpline { half_order, x: x.to_vec(), coefficients: fit(half_order, x, y, smoothing), buckets }
    }

    pub(super) fn value(&self, x: f64) -> f64 {
        let l = self.interval(x);
        if self.half_order == 2 && l >= 3 && l + 3 <= self.x.len() {
            return self.interior_cubic_value(x, l);
        }
        self.derivative_of_order(0, x, l)
    }

    pub(super) fn derivative(&self, x: f64) -> f64 {
        self.derivative_of_order(1, x, self.interval(x))
    }

    pub(super) fn second_derivative(&self, x: f64) -> f64 {
        self.derivative_of_order(2, x, self.interval(x))
    }

    pub(super) fn value_and_derivative(&self, x: f64) -> (f64, f64) {
        let l = self.interval(x);
        (self.derivative_of_order(0, x, l), self.derivative_of_order(1, x, l))
    }

    /// GCVSPL's `SEARCH`: l with x_l ≤ t < x_{l+1} (1-based), 0 before x_1 (and for NaN), n
    /// from x_n on. Starts from t's bucket and steps to the interval, usually at once.
    #[inline]
    fn interval(&self, t: f64) -> usize {
        let mut l = self.buckets.start(self.x[0], t);
        while l < self.x.len() && self.x[l] <= t {
            l += 1;
        }
        while l > 0 && self.x[l - 1] > t {
            l -= 1;
        }
        l
    }

    /// GCVSPL's `SPLDER`: the `order`-th derivative at t in interval l. Takes the 2m
    /// coefficients that act on the interval, differences them `order` times (divided by
    /// knot spans, mirrored below the first knot), runs the de Boor-type recursion down to
    /// one value and multiplies by (2m − 1)!/(2m − 1 − order)!.
    fn derivative_of_order(&self, order: usize, t: f64, l: usize) -> f64 {
        let m = self.half_order as isize;
        let (l, order) = (l as isize, order as isize);
        let m2 = 2 * m;
        let k = m2 - order;
        if k < 1 {
            return 0.0;
        }
        let mut q = self.local_coefficients(l);
        if order > 0 {
            self.difference(&mut q, order, l);
        }
        self.reduce(&mut q, k, t, l);
        (k..m2).fold(q[k as usize], |z, j| z * j as f64)
    }

    /// q_s = c_{l−m+s} for s = 1…2m, zero for indices outside 1…n.
    fn local_coefficients(&self, l: isize) -> Window {
        let (m, n) = (self.half_order as isize, self.x.len() as isize);
        let mut q = [0.0; 2 * MAX_HALF_ORDER + 1];
        for s in 1..=2 * m {
            let index = l + s - m;
            if (1..=n).contains(&index) {
                q[s as usize] = self.coefficients[(index - 1) as usize];
            }
        }
        q
    }

    /// `SPLDER`'s value for a cubic (m = 2) in an interval l with 3 ≤ l ≤ n − 3, where every
    /// knot the recursion touches exists: the same operations in the same order, unrolled.
    fn interior_cubic_value(&self, t: f64, l: usize) -> f64 {
        let c = &self.coefficients[l - 2..l + 2];
        let x = &self.x[l - 3..l + 3];
        let sweep = |z: f64, below: f64, left: f64, right: f64| z + (right - t) * (below - z) / (right - left);
        let (q1, q2, q3, q4) = (c[0], c[1], c[2], c[3]);
        let q4 = sweep(q4, q3, x[2], x[5]);
        let q3 = sweep(q3, q2, x[1], x[4]);
        let q2 = sweep(q2, q1, x[0], x[3]);
        let q4 = sweep(q4, q3, x[2], x[4]);
        let q3 = sweep(q3, q2, x[1], x[3]);
        sweep(q4, q3, x[2], x[3])
    }

    /// Divided differences of the local coefficients, `order` times, shifted down to q_1….
    fn difference(&self, q: &mut Window, order: isize, l: isize) {
        let (m2, n) = (2 * self.half_order as isize, self.x.len() as isize);
        let knot = |j: isize| self.x[(j - 1) as usize];
        let at = |slot: isize| slot as usize;
        let shift = m2 - l;
        for i in 1..=order {
            let lowest = l + 1 - m2 + i;
            let span = m2 - i;
            for j in (lowest.max(1)..=l.min(n - m2 + i)).rev() {
                let s = shift + j;
                q[at(s)] = (q[at(s)] - q[at(s - 1)]) / (knot(j + span) - knot(j));
            }
            if lowest < 1 {
                for s in (i + 1..=shift).rev() {
                    q[at(s)] = -q[at(s - 1)];
                }
            }
        }
        for s in 1..=(m2 - order) {
            q[at(s)] = q[at(s + order)];
        }
    }

    /// Collapses q_1…q_k to the value q_k at t, k − 1 convex-combination sweeps; knots
    /// beyond x_n and before x_1 drop out of the weights as GCVSPL's natural extension.
    fn reduce(&self, q: &mut Window, k: isize, t: f64, l: isize) {
        let n = self.x.len() as isize;
        let knot = |j: isize| self.x[(j - 1) as usize];
        let at = |slot: isize| slot as usize;
        for i in 1..k {
            let (last_inside, ki) = (n - k + i, k - i);
            let (mut ir, mut jj) = (k, l);
            for _ in last_inside + 1..=l {
                q[at(ir)] = q[at(ir - 1)] + (t - knot(jj)) * q[at(ir)];
                jj -= 1;
                ir -= 1;
            }
            let first_inside = l - k + 1 + i;
            for _ in first_inside.max(1)..=l.min(last_inside) {
                let right = knot(jj + ki);
                let z = q[at(ir)];
                q[at(ir)] = z + (right - t) * (q[at(ir - 1)] - z) / (right - knot(jj));
                ir -= 1;
                jj -= 1;
            }
            if first_inside <= 0 {
                jj = ki;
                for _ in 0..1 - first_inside {
                    q[at(ir)] += (knot(jj) - t) * q[at(ir - 1)];
                    jj -= 1;
                    ir -= 1;
                }
            }
        }
    }
}

impl KnotBuckets {
    /// n buckets over the increasing knots `x`.
    fn new(x: &[f64]) -> KnotBuckets {
        let n = x.len();
        let per_width = n as f64 / (x[n - 1] - x[0]);
        let first = (0..n).map(|b| x.partition_point(|&knot| knot < x[0] + b as f64 / per_width)).collect();
        KnotBuckets { per_width, first }
    }

    /// Where to start looking for t's interval: the knot count at the lower edge of t's bucket
    /// (the first or last bucket outside [x_1, x_n], the first for NaN).
    fn start(&self, x_1: f64, t: f64) -> usize {
        let bucket = ((t - x_1) * self.per_width) as usize;
        self.first[bucket.min(self.first.len() - 1)]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::Value;
    use std::path::Path;

    fn golden(file: &str) -> String {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/golden/functions").join(file);
        std::fs::read_to_string(path).unwrap()
    }

    /// The bucketed search finds GCVSPL's interval (the number of knots ≤ t) everywhere: on,
    /// between, before and after the knots of unevenly spaced data, and for NaN.
    #[test]
    fn interval_counts_the_knots_at_or_below_t() {
        let x: Vec<f64> = (0..40).map(|i| (i as f64 * 0.37).powi(3) - 20.0).collect();
        let y: Vec<f64> = x.iter().map(|v| v.sin()).collect();
        let spline = GcvSpline::new(3, &x, &y, Smoothing::ErrorVariance(0.0));
        let mut probes = vec![f64::NAN, f64::NEG_INFINITY, f64::INFINITY, x[0] - 1.0, x[39] + 1.0];
        for w in x.windows(2) {
            probes.extend([w[0], w[0].next_up(), w[0].next_down(), 0.5 * (w[0] + w[1])]);
        }
        for t in probes {
            assert_eq!(spline.interval(t), x.partition_point(|&knot| knot <= t), "t = {t:?}");
        }
    }

    /// The smoothing variants `FunctionSpec` cannot express yet, against OpenSim 4.6.
    #[test]
    fn smoothed_fits_match_opensim_to_the_bit() {
        let definitions: Value = serde_json::from_str(&golden("definitions.json")).unwrap();
        // Numbers are stored as text: serde_json's float parsing is not always correctly rounded.
        let numbers = |d: &Value, key: &str| -> Vec<f64> {
            d[key].as_str().unwrap().split_whitespace().map(|v| v.parse().unwrap()).collect()
        };
        let mut checked = 0;
        for definition in definitions["functions"].as_array().unwrap() {
            if definition.get("error_variance").is_none() {
                continue;
            }
            let error_variance = numbers(definition, "error_variance")[0];
            let degree = definition["degree"].as_u64().unwrap() as usize;
            let smoothing = Smoothing::from_error_variance(error_variance);
            let spline = GcvSpline::new(degree, &numbers(definition, "x"), &numbers(definition, "y"), smoothing);
            let name = definition["name"].as_str().unwrap();
            for line in golden(&format!("{name}.csv")).lines().skip(1) {
                let row: Vec<f64> = line.split(',').map(|f| f.parse().unwrap()).collect();
                let x = row[0];
                let found = [spline.value(x), spline.derivative(x), spline.second_derivative(x)];
                assert_eq!(found, [row[1], row[2], row[3]], "{name} at x = {x:?}");
            }
            checked += 1;
        }
        assert_eq!(checked, 2, "error-variance and cross-validated fits");
    }
}
