//! `Body::scaleInertialProperties` and `Body::scaleMass`: a body's mass and inertia after its
//! geometry is scaled, in OpenSim's operation order.

/// Mass (kg) and inertia about the mass center in the body frame (kg·m²), in OpenSim 4's
/// property order Ixx Iyy Izz Ixy Ixz Iyz.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Inertial {
    pub mass: f64,
    pub inertia: [f64; 6],
}

/// SimTK's `SignificantReal`, the default tolerance of `isNumericallyEqual`.
fn significant_real() -> f64 {
    f64::EPSILON.powf(0.875)
}

/// SimTK's `isNumericallyEqual` at its default tolerance.
fn numerically_equal(a: f64, b: f64) -> bool {
    (a - b).abs() <= a.abs().max(b.abs()).max(1.0) * significant_real()
}

impl Inertial {
    /// After scaling the body by `factors`: the mass times |sx·sy·sz| when `scale_mass`; the
    /// inertia exactly by s² for uniform factors, otherwise through OpenSim's cylinder model
    /// (axis = the smallest principal moment) with products of inertia scaled by the two
    /// factors of their axes.
    pub fn scaled(self, factors: [f64; 3], scale_mass: bool) -> Inertial {
        let unscaled_mass = self.mass;
        let mass_scale = (factors[0] * factors[1] * factors[2]).abs();
        let mass = if scale_mass { self.mass * mass_scale } else { self.mass };
        let mut i = full(self.inertia);
        if mass <= f64::EPSILON {
            i = [[0.0; 3]; 3];
        } else if numerically_equal(factors[0], factors[1]) && numerically_equal(factors[1], factors[2]) {
            for value in i.iter_mut().flatten() {
                if scale_mass {
                    *value *= mass_scale;
                }
                *value *= factors[0] * factors[0];
            }
        } else {
            cylinder(&mut i, factors, unscaled_mass, mass);
            for (r, c) in [(0, 1), (0, 2), (1, 0), (1, 2), (2, 0), (2, 1)] {
                i[r][c] *= factors[r] * factors[c];
                if scale_mass {
                    i[r][c] *= mass_scale;
                }
            }
        }
        Inertial { mass, inertia: [i[0][0], i[1][1], i[2][2], i[0][1], i[0][2], i[1][2]] }
    }

    /// `Body::scaleMass`: mass and inertia times `factor`.
    pub fn mass_scaled(self, factor: f64) -> Inertial {
        Inertial { mass: self.mass * factor, inertia: self.inertia.map(|v| factor * v) }
    }
}

fn full(i: [f64; 6]) -> [[f64; 3]; 3] {
    [[i[0], i[3], i[4]], [i[3], i[1], i[5]], [i[4], i[5], i[2]]]
}

/// The diagonal of a solid cylinder along the axis of the smallest moment, its radius and
/// length recovered from the unscaled moments and rescaled by `factors`.
fn cylinder(i: &mut [[f64; 3]; 3], factors: [f64; 3], unscaled_mass: f64, mass: f64) {
    let axis = if i[0][0] <= i[1][1] {
        if i[0][0] <= i[2][2] { 0 } else { 2 }
    } else if i[1][1] <= i[2][2] {
        1
    } else {
        2
    };
    let term = 2.0 * i[axis][axis] / unscaled_mass;
    let radius = if term < 0.0 { 0.0 } else { term.sqrt() };
    let other = if axis == 0 { 1 } else { 0 };
    let term = 12.0 * (i[other][other] - 0.25 * unscaled_mass * radius * radius) / unscaled_mass;
    let mut length = if term < 0.0 { 0.0 } else { term.sqrt() };
    length *= factors[axis];
    let [a, b] = match axis {
        0 => [1, 2],
        1 => [0, 2],
        _ => [0, 1],
    };
    let rad_sqr = radius * factors[a] * radius * factors[b];
    let across = mass * ((length * length / 12.0) + 0.25 * rad_sqr);
    for (k, row) in i.iter_mut().enumerate() {
        row[k] = if k == axis { 0.5 * mass * rad_sqr } else { across };
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Solid cylinder of mass m, radius r, length l along y, about its center.
    fn cylinder_y(m: f64, r: f64, l: f64) -> Inertial {
        let across = m * (l * l / 12.0 + r * r / 4.0);
        Inertial { mass: m, inertia: [across, 0.5 * m * r * r, across, 0.0, 0.0, 0.0] }
    }

    #[test]
    fn uniform_scaling_multiplies_inertia_by_mass_and_length_squared() {
        let body = Inertial { mass: 2.0, inertia: [0.1, 0.2, 0.3, 0.01, -0.02, 0.03] };
        let scaled = body.scaled([1.5; 3], true);
        assert!((scaled.mass - 2.0 * 3.375).abs() < 1e-14);
        for (new, old) in scaled.inertia.iter().zip(body.inertia) {
            assert!((new - old * 3.375 * 2.25).abs() < 1e-14);
        }
        let kept = body.scaled([1.5; 3], false);
        assert_eq!(kept.mass, 2.0);
        assert!((kept.inertia[1] - 0.2 * 2.25).abs() < 1e-15);
    }

    #[test]
    fn a_cylinder_scaled_along_and_across_its_axis_stays_a_cylinder() {
        let (m, r, l) = (3.0, 0.05, 0.4);
        let scaled = cylinder_y(m, r, l).scaled([1.2, 0.9, 1.2], false);
        let expected = cylinder_y(m, r * 1.2, l * 0.9);
        for (a, b) in scaled.inertia.iter().zip(expected.inertia) {
            assert!((a - b).abs() < 1e-15, "{a} vs {b}");
        }
    }

    #[test]
    fn a_massless_body_gets_zero_inertia_and_mass_scaling_is_linear() {
        let body = Inertial { mass: 0.0, inertia: [1.0, 1.0, 1.0, 0.0, 0.0, 0.0] };
        assert_eq!(body.scaled([2.0, 1.0, 1.0], true).inertia, [0.0; 6]);
        let body = Inertial { mass: 2.0, inertia: [0.1, 0.2, 0.3, 0.0, 0.0, 0.0] };
        assert_eq!(body.mass_scaled(0.5), Inertial { mass: 1.0, inertia: [0.05, 0.1, 0.15, 0.0, 0.0, 0.0] });
    }
}
