//! OpenSim's `PolynomialFunction`, which OpenSim evaluates as Simbody's
//! `Function::Polynomial`: coefficients from the highest power down, Horner's rule.

/// y = a_0·x^p + a_1·x^(p−1) + … + a_p, with the derivatives' coefficients precomputed.
#[derive(Debug, Clone)]
pub(super) struct Polynomial {
    coefficients: Vec<f64>,
    /// a_i·(p − i) for i < p: coefficients of dy/dx, highest power first.
    first: Vec<f64>,
    /// a_i·(p − i)·(p − i − 1) for i < p − 1: coefficients of d²y/dx².
    second: Vec<f64>,
}

impl Polynomial {
    pub(super) fn new(coefficients: &[f64]) -> Polynomial {
        Polynomial {
            coefficients: coefficients.to_vec(),
            first: differentiated(coefficients, 1),
            second: differentiated(coefficients, 2),
        }
    }

    pub(super) fn value(&self, x: f64) -> f64 {
        horner(&self.coefficients, x)
    }

    pub(super) fn derivative(&self, x: f64) -> f64 {
        horner(&self.first, x)
    }

    pub(super) fn second_derivative(&self, x: f64) -> f64 {
        horner(&self.second, x)
    }
}

/// Coefficients of the `order`-th derivative: a_i·(p−i)·(p−i−1)·…, multiplied factor by
/// factor in Simbody's order (so values agree to the bit). Empty when order > p.
fn differentiated(coefficients: &[f64], order: usize) -> Vec<f64> {
    let power = |i: usize| coefficients.len() - 1 - i;
    let kept = coefficients.len().saturating_sub(order);
    (0..kept).map(|i| (0..order).fold(coefficients[i], |a, j| a * (power(i) - j) as f64)).collect()
}

/// ((a_0·x + a_1)·x + …)·x + a_p, starting from 0 as Simbody does (0 for no coefficients).
fn horner(coefficients: &[f64], x: f64) -> f64 {
    coefficients.iter().fold(0.0, |value, a| value * x + a)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn highest_power_first() {
        // 2x³ − x + 4
        let p = Polynomial::new(&[2.0, 0.0, -1.0, 4.0]);
        assert_eq!(p.value(2.0), 18.0);
        assert_eq!(p.derivative(2.0), 23.0);
        assert_eq!(p.second_derivative(2.0), 24.0);
    }

    #[test]
    fn derivatives_of_a_constant_vanish() {
        let p = Polynomial::new(&[1.25]);
        assert_eq!((p.value(3.0), p.derivative(3.0), p.second_derivative(3.0)), (1.25, 0.0, 0.0));
        assert_eq!(Polynomial::new(&[]).value(1.0), 0.0);
    }
}
