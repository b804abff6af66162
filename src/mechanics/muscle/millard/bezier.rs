//! OpenSim's `SegmentedQuinticBezierToolkit`: quintic Bézier segments x(u), y(u), u ∈ [0, 1],
//! their u-derivatives written term by term as OpenSim writes them (so results agree to the
//! bit), dy/dx and d²y/dx², and the C-shaped corner whose six control points make a segment.
//! Not OpenSim's: the same segment in power form, which evaluates x, y and their slopes in
//! about half the operations, to an ulp (the curves' hot path).

/// The control points of one quintic Bézier segment.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BezierSegment {
    pub x: [f64; 6],
    pub y: [f64; 6],
}

/// Why a corner cannot be built.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct NotACorner;

impl BezierSegment {
    /// `calcQuinticBezierCornerControlPoints`: a segment from (x0, y0) with slope dydx0 to
    /// (x1, y1) with slope dydx1, bending towards the intersection of the two tangent lines;
    /// curviness ∈ [0, 1] places the inner points along the tangents.
    pub fn corner(
        (x0, y0, dydx0): (f64, f64, f64),
        (x1, y1, dydx1): (f64, f64, f64),
        curviness: f64,
    ) -> Result<BezierSegment, NotACorner> {
        let root_eps = f64::EPSILON.sqrt();
        let xc = if (dydx0 - dydx1).abs() > root_eps {
            (y1 - y0 - x1 * dydx1 + x0 * dydx0) / (dydx0 - dydx1)
        } else {
            (x1 + x0) / 2.0
        };
        let yc = (xc - x1) * dydx1 + y1;
        let (xc_x0, yc_y0, xc_x1, yc_y1) = (xc - x0, yc - y0, xc - x1, yc - y1);
        let (x0_x1, y0_y1) = (x1 - x0, y1 - y0);
        let a = xc_x0 * xc_x0 + yc_y0 * yc_y0;
        let b = xc_x1 * xc_x1 + yc_y1 * yc_y1;
        let c = x0_x1 * x0_x1 + y0_y1 * y0_y1;
        if !(c > a && c > b) {
            return Err(NotACorner);
        }
        let x0_mid = x0 + curviness * xc_x0;
        let y0_mid = y0 + curviness * yc_y0;
        let x1_mid = x1 + curviness * xc_x1;
        let y1_mid = y1 + curviness * yc_y1;
        Ok(BezierSegment {
            x: [x0, x0_mid, x0_mid, x1_mid, x1_mid, x1],
            y: [y0, y0_mid, y0_mid, y1_mid, y1_mid, y1],
        })
    }

    /// The segment with x and y exchanged (the inverse relation).
    pub fn transposed(&self) -> BezierSegment {
        BezierSegment {
            x: self.y,
            y: self.x,
        }
    }

    /// d^order y / dx^order at parameter u, order 0, 1 or 2 (`calcQuinticBezierCurveDerivDYDX`).
    #[inline]
    pub fn dydx(&self, u: f64, order: usize) -> f64 {
        match order {
            0 => derivative_u(u, &self.y, 0),
            1 => {
                let first = Weights::at(u, 1);
                first.apply(&self.y) / first.apply(&self.x)
            }
            _ => {
                let (first, second) = (Weights::at(u, 1), Weights::at(u, 2));
                let dxdu = first.apply(&self.x);
                let dydu = first.apply(&self.y);
                let d2xdu2 = second.apply(&self.x);
                let d2ydu2 = second.apply(&self.y);
                let t1 = 1.0 / dxdu;
                let t3 = dxdu * dxdu;
                (d2ydu2 * t1 - dydu / t3 * d2xdu2) * t1
            }
        }
    }
}

/// A segment in power form: x(u) = Σ a_k u^k and y(u) likewise, with the coefficients of dx/du
/// and dy/du. The coefficients are formed from the control points' offsets from the first one
/// (exact for points within a factor 2 of it), so x(u) and y(u) round to about an ulp — OpenSim's
/// expanded Bernstein weights to ~30 ulp near u = 1.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PowerSegment {
    x: [f64; 6],
    y: [f64; 6],
    dxdu: [f64; 5],
    dydu: [f64; 5],
}

impl PowerSegment {
    pub fn new(segment: &BezierSegment) -> PowerSegment {
        let (x, y) = (power_coefficients(&segment.x), power_coefficients(&segment.y));
        PowerSegment { x, y, dxdu: derivative_coefficients(&x), dydu: derivative_coefficients(&y) }
    }

    #[inline]
    pub fn x(&self, u: f64) -> f64 {
        quintic(&self.x, u)
    }

    #[inline]
    pub fn y(&self, u: f64) -> f64 {
        quintic(&self.y, u)
    }

    #[inline]
    pub fn dxdu(&self, u: f64) -> f64 {
        quartic(&self.dxdu, u)
    }

    /// dy/dx at u.
    #[inline]
    pub fn dydx(&self, u: f64) -> f64 {
        quartic(&self.dydu, u) / quartic(&self.dxdu, u)
    }

    /// (d²x/du², d³x/du³) at u.
    pub fn higher_x_derivatives(&self, u: f64) -> (f64, f64) {
        let a = &self.x;
        let second = 2.0 * a[2] + u * (6.0 * a[3] + u * (12.0 * a[4] + u * 20.0 * a[5]));
        let third = 6.0 * a[3] + u * (24.0 * a[4] + u * 60.0 * a[5]);
        (second, third)
    }
}

/// Power-form coefficients a_k = C(5, k) Σ_{i ≤ k} (−1)^(k−i) C(k, i) p_i of a quintic Bézier
/// with control values `p`, written with the offsets d_i = p_i − p_0 (the p_0 terms cancel).
fn power_coefficients(p: &[f64; 6]) -> [f64; 6] {
    let d = p.map(|v| v - p[0]);
    [
        p[0],
        5.0 * d[1],
        10.0 * (d[2] - 2.0 * d[1]),
        10.0 * (d[3] - 3.0 * d[2] + 3.0 * d[1]),
        5.0 * (d[4] - 4.0 * d[3] + 6.0 * d[2] - 4.0 * d[1]),
        d[5] - 5.0 * d[4] + 10.0 * d[3] - 10.0 * d[2] + 5.0 * d[1],
    ]
}

/// The coefficients of the derivative of Σ a_k u^k.
fn derivative_coefficients(a: &[f64; 6]) -> [f64; 5] {
    [a[1], 2.0 * a[2], 3.0 * a[3], 4.0 * a[4], 5.0 * a[5]]
}

/// Σ a_k u^k, k ≤ 5, by Estrin's scheme (shorter dependency chains than Horner's).
#[inline]
fn quintic(a: &[f64; 6], u: f64) -> f64 {
    let u2 = u * u;
    (a[0] + a[1] * u) + u2 * ((a[2] + a[3] * u) + u2 * (a[4] + a[5] * u))
}

/// Σ a_k u^k, k ≤ 4, by Estrin's scheme.
#[inline]
fn quartic(a: &[f64; 5], u: f64) -> f64 {
    let u2 = u * u;
    (a[0] + a[1] * u) + u2 * ((a[2] + a[3] * u) + u2 * a[4])
}

/// d^order p/du^order of a quintic Bézier with control values `p`, order 0, 1 or 2
/// (`calcQuinticBezierCurveDerivU`, same operation order).
#[inline]
pub fn derivative_u(u: f64, p: &[f64; 6], order: usize) -> f64 {
    Weights::at(u, order).apply(p)
}

/// What `calcQuinticBezierCurveDerivU` multiplies the control values by at one u and order:
/// it sums p0·w0 + … + p4·w4 + p5·w5·c5 left to right, each w_k a term of u alone, so one set
/// of weights serves x and y with OpenSim's operations unchanged.
#[derive(Debug, Clone, Copy)]
pub struct Weights {
    w: [f64; 6],
    /// The constant OpenSim multiplies p5·w5 by (after the product, not folded into w5).
    c5: f64,
}

impl Weights {
    /// The weights of derivative order 0, 1 or 2 at u.
    #[inline]
    pub fn at(u: f64, order: usize) -> Weights {
        match order {
            0 => {
                let u5 = 1.0;
                let u4 = u;
                let u3 = u4 * u;
                let u2 = u3 * u;
                let u1 = u2 * u;
                let u0 = u1 * u;
                let t2 = u1 * 5.0;
                let t3 = u2 * 10.0;
                let t4 = u3 * 10.0;
                let t5 = u4 * 5.0;
                let t9 = u0 * 5.0;
                let t10 = u1 * 20.0;
                let t11 = u2 * 30.0;
                let t15 = u0 * 10.0;
                let w = [
                    -u0 + t2 - t3 + t4 - t5 + u5 * 1.0,
                    t9 - t10 + t11 + u3 * (-20.0) + t5,
                    -t15 + u1 * 30.0 - t11 + t4,
                    t15 - t10 + t3,
                    -t9 + t2,
                    u0,
                ];
                Weights { w, c5: 1.0 }
            }
            1 => {
                let t1 = u * u;
                let t2 = t1 * t1;
                let t4 = t1 * u;
                let t5 = t4 * 20.0;
                let t6 = t1 * 30.0;
                let t7 = u * 20.0;
                let t10 = t2 * 25.0;
                let t11 = t4 * 80.0;
                let t12 = t1 * 90.0;
                let t16 = t2 * 50.0;
                let w = [
                    t2 * (-5.0) + t5 - t6 + t7 - 5.0,
                    t10 - t11 + t12 + u * (-40.0) + 5.0,
                    -t16 + t4 * 120.0 - t12 + t7,
                    t16 - t11 + t6,
                    -t10 + t5,
                    t2,
                ];
                Weights { w, c5: 5.0 }
            }
            _ => {
                let t1 = u * u;
                let t2 = t1 * u;
                let t4 = t1 * 60.0;
                let t5 = u * 60.0;
                let t8 = t2 * 100.0;
                let t9 = t1 * 240.0;
                let t10 = u * 180.0;
                let t13 = t2 * 200.0;
                let w = [
                    t2 * (-20.0) + t4 - t5 + 20.0,
                    t8 - t9 + t10 - 40.0,
                    -t13 + t1 * 360.0 - t10 + 20.0,
                    t13 - t9 + t5,
                    -t8 + t4,
                    t2,
                ];
                Weights { w, c5: 20.0 }
            }
        }
    }

    /// The derivative for control values `p`.
    #[inline]
    pub fn apply(&self, p: &[f64; 6]) -> f64 {
        let w = &self.w;
        p[0] * w[0] + p[1] * w[1] + p[2] * w[2] + p[3] * w[3] + p[4] * w[4] + p[5] * w[5] * self.c5
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_corner_interpolates_its_ends_with_their_slopes() {
        let s = BezierSegment::corner((0.0, 0.0, 0.0), (1.0, 1.0, 3.0), 0.5).unwrap();
        assert_eq!((derivative_u(0.0, &s.x, 0), s.dydx(0.0, 0)), (0.0, 0.0));
        assert_eq!((derivative_u(1.0, &s.x, 0), s.dydx(1.0, 0)), (1.0, 1.0));
        assert!(s.dydx(0.0, 1).abs() < 1e-15);
        assert!((s.dydx(1.0, 1) - 3.0).abs() < 1e-12);
    }

    #[test]
    fn u_derivatives_match_central_differences() {
        let p = [0.1, 0.7, 0.2, 1.5, -0.3, 2.0];
        for u in [0.1, 0.45, 0.9] {
            let h = 1e-6;
            for order in 1..=2 {
                let fd = (derivative_u(u + h, &p, order - 1) - derivative_u(u - h, &p, order - 1))
                    / (2.0 * h);
                assert!(
                    (fd - derivative_u(u, &p, order)).abs() < 1e-7,
                    "order {order} at {u}"
                );
            }
        }
    }

    #[test]
    fn the_power_form_equals_the_bernstein_form() {
        let s = BezierSegment::corner((1.0, 0.0, 0.0), (1.03, 0.6, 30.0), 0.5).unwrap();
        let power = PowerSegment::new(&s);
        for i in 0..=20 {
            let u = i as f64 / 20.0;
            // OpenSim's expanded Bernstein weights round to ~30 ulp near u = 1.
            assert!((power.x(u) - derivative_u(u, &s.x, 0)).abs() < 1e-14, "x at {u}");
            assert!((power.y(u) - derivative_u(u, &s.y, 0)).abs() < 1e-14, "y at {u}");
            assert!((power.dxdu(u) - derivative_u(u, &s.x, 1)).abs() < 1e-14, "dx/du at {u}");
            assert!((power.dydx(u) - s.dydx(u, 1)).abs() < 1e-12 * s.dydx(u, 1).abs().max(1.0), "dy/dx at {u}");
            let (second, third) = power.higher_x_derivatives(u);
            assert!((second - derivative_u(u, &s.x, 2)).abs() < 1e-12, "d²x/du² at {u}");
            let h = 1e-6;
            let fd = (derivative_u(u + h, &s.x, 2) - derivative_u(u - h, &s.x, 2)) / (2.0 * h);
            assert!((third - fd).abs() < 1e-6, "d³x/du³ at {u}");
        }
    }

    #[test]
    fn an_impossible_corner_is_refused() {
        // Both tangents point away from each other: no C-shaped corner joins them.
        assert_eq!(
            BezierSegment::corner((0.0, 0.0, -1.0), (1.0, 1.0, -1.0), 0.5),
            Err(NotACorner)
        );
    }
}
