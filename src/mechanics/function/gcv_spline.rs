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
}

/// Room for the 2m local coefficients, 1-based as in `SPLDER` (slot 0 unused).
type Window = [f64; 2 * MAX_HALF_ORDER + 1];

impl GcvSpline {
    /// Fits degree `degree` (odd, n ≥ degree + 1 points) as `GCVSpline::createSimTKFunction`.
    pub(super) fn new(degree: usize, x: &[f64], y: &[f64], smoothing: Smoothing) -> GcvSpline {
        let half_order = degree.div_ceil(2).clamp(1, MAX_HALF_ORDER);
        GcvSpline { half_order, x: x.to_vec(), coefficients: fit(half_order, x, y, smoothing) }
    }

    pub(super) fn value(&self, x: f64) -> f64 {
        self.derivative_of_order(0, x, self.interval(x))
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

    /// GCVSPL's `SEARCH`: l with x_l ≤ t < x_{l+1} (1-based), 0 before x_1, n from x_n on.
    fn interval(&self, t: f64) -> usize {
        self.x.partition_point(|&knot| knot <= t)
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

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::Value;
    use std::path::Path;

    fn golden(file: &str) -> String {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/golden/functions").join(file);
        std::fs::read_to_string(path).unwrap()
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
