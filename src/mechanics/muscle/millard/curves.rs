//! The Millard 2012 curves built as OpenSim's `SmoothSegmentedFunctionFactory` builds them,
//! with the parameter checks OpenSim makes (an invalid parameter is an error, never a curve).

use super::bezier::{BezierSegment, NotACorner};
use super::smooth_function::SmoothSegmentedFunction;
use crate::model::ForceVelocityCurveSpec;

/// A curve parameter OpenSim refuses.
#[derive(Debug, Clone, PartialEq)]
pub struct CurveError {
    /// Curve class and property, e.g. `ActiveForceLengthCurve.min_norm_active_fiber_length`.
    pub property: String,
    pub value: f64,
    pub expected: String,
}

fn require(ok: bool, property: &str, value: f64, expected: &str) -> Result<(), CurveError> {
    if ok {
        Ok(())
    } else {
        Err(CurveError {
            property: property.into(),
            value,
            expected: expected.into(),
        })
    }
}

/// `scaleCurviness`: curviness ∈ [0, 1] → the Bézier corner's 0.1…0.9.
fn scale_curviness(curviness: f64) -> f64 {
    0.1 + 0.8 * curviness
}

fn check_curviness(property: &str, curviness: f64) -> Result<(), CurveError> {
    require(
        (0.0..=1.0).contains(&curviness),
        property,
        curviness,
        "a curviness in [0, 1]",
    )
}

fn corners(
    points: &[(f64, f64, f64)],
    curviness: f64,
    property: &str,
) -> Result<Vec<BezierSegment>, CurveError> {
    points
        .windows(2)
        .map(|w| BezierSegment::corner(w[0], w[1], curviness))
        .collect::<Result<_, NotACorner>>()
        .map_err(|NotACorner| CurveError {
            property: property.into(),
            value: f64::NAN,
            expected: "parameters whose tangent lines meet in a C-shaped corner".into(),
        })
}

/// `createFiberActiveForceLengthCurve(x0, x1, x2, x3, ylow, dydx, curviness)`: zero-slope
/// shoulders at ylow below x0 and above x3, a peak of 1 at x2, a shallow ascending slope dydx
/// between the transition x1 and x2.
pub fn active_force_length(
    x: [f64; 4],
    ylow: f64,
    dydx: f64,
    curviness: f64,
) -> Result<SmoothSegmentedFunction, CurveError> {
    const P: &str = "ActiveForceLengthCurve";
    let [x0, x1, x2, x3] = x;
    let root_eps = f64::EPSILON.sqrt();
    let ordered = x0 >= 0.0 && x1 > x0 + root_eps && x2 > x1 + root_eps && x3 > x2 + root_eps;
    require(
        ordered,
        &format!("{P}.min_norm_active_fiber_length"),
        x0,
        "0 ≤ min < transition < 1 < max normalised fiber length",
    )?;
    require(
        ylow >= 0.0,
        &format!("{P}.minimum_value"),
        ylow,
        "a value ≥ 0",
    )?;
    let dydx_upper = (1.0 - ylow) / (x2 - x1);
    require(
        dydx >= 0.0 && dydx < dydx_upper,
        &format!("{P}.shallow_ascending_slope"),
        dydx,
        &format!("a slope in [0, {dydx_upper})"),
    )?;
    check_curviness(P, curviness)?;
    let c = scale_curviness(curviness);
    let x_delta = 0.05 * x2;
    let xs = x2 - x_delta;
    let (y0, dydx0) = (0.0, 0.0);
    let y1 = 1.0 - dydx * (xs - x1);
    let dydx01 = 1.25 * (y1 - y0) / (x1 - x0);
    let x01 = x0 + 0.5 * (x1 - x0);
    let y01 = y0 + 0.5 * (y1 - y0);
    let x1s = x1 + 0.5 * (xs - x1);
    let y1s = y1 + 0.5 * (1.0 - y1);
    let (y2, dydx2, y3, dydx3) = (1.0, 0.0, 0.0, 0.0);
    let x23 = (x2 + x_delta) + 0.5 * (x3 - (x2 + x_delta));
    let y23 = y2 + 0.5 * (y3 - y2);
    let dydx23 = (y3 - y2) / ((x3 - x_delta) - (x2 + x_delta));
    let points = [
        (x0, ylow, dydx0),
        (x01, y01, dydx01),
        (x1s, y1s, dydx),
        (x2, y2, dydx2),
        (x23, y23, dydx23),
        (x3, ylow, dydx3),
    ];
    let segments = corners(&points, c, P)?;
    Ok(SmoothSegmentedFunction::new(
        segments,
        (x0, ylow, 0.0),
        (x3, ylow, 0.0),
    ))
}

/// The four corners of a force–velocity curve, from −1 (v_max shortening, 0 force) to +1
/// (v_max lengthening, fmaxE): `createFiberForceVelocityCurve`'s construction.
fn force_velocity_segments(s: &ForceVelocityCurveSpec) -> Result<Vec<BezierSegment>, CurveError> {
        let (cc, ce) = (
            scale_curviness(s.concentric_curviness),
            scale_curviness(s.eccentric_curviness),
        );
        let (xc, yc, x_near_c) = (-1.0, 0.0, -0.9);
        let y_near_c = yc
            + 0.5 * s.concentric_slope_near_vmax * (x_near_c - xc)
            + 0.5 * s.concentric_slope_at_vmax * (x_near_c - xc);
        let (x_iso, y_iso, xe, ye, x_near_e) = (
            0.0,
            1.0,
            1.0,
            s.max_eccentric_velocity_force_multiplier,
            0.9,
        );
        let y_near_e = ye
            + 0.5 * s.eccentric_slope_near_vmax * (x_near_e - xe)
            + 0.5 * s.eccentric_slope_at_vmax * (x_near_e - xe);
        let concentric = [
            (xc, yc, s.concentric_slope_at_vmax),
            (x_near_c, y_near_c, s.concentric_slope_near_vmax),
            (x_iso, y_iso, s.isometric_slope),
        ];
        let eccentric = [
            (x_iso, y_iso, s.isometric_slope),
            (x_near_e, y_near_e, s.eccentric_slope_near_vmax),
            (xe, ye, s.eccentric_slope_at_vmax),
        ];
        let mut segments = corners(&concentric, cc, "ForceVelocityCurve")?;
        segments.extend(corners(&eccentric, ce, "ForceVelocityCurve")?);
        Ok(segments)
}

/// OpenSim's checks on a force–velocity curve; the inverse also needs positive end slopes.
fn check_force_velocity(s: &ForceVelocityCurveSpec, inverse: bool) -> Result<(), CurveError> {
        const P: &str = "ForceVelocityCurve";
        let fmax = s.max_eccentric_velocity_force_multiplier;
        let tiny = if inverse {
            super::super::pennation::SIGNIFICANT_REAL
        } else {
            0.0
        };
        let at_vmax_ok = |slope: f64| if inverse { slope > tiny } else { slope >= 0.0 };
        require(
            fmax > 1.0,
            &format!("{P}.max_eccentric_velocity_force_multiplier"),
            fmax,
            "a value > 1",
        )?;
        let c = s.concentric_slope_at_vmax;
        require(
            at_vmax_ok(c) && c < 1.0,
            &format!("{P}.concentric_slope_at_vmax"),
            c,
            "a slope in [0, 1)",
        )?;
        let near_c = s.concentric_slope_near_vmax;
        let near_c_ok = near_c > c && if inverse { near_c < 1.0 } else { near_c <= 1.0 };
        require(
            near_c_ok,
            &format!("{P}.concentric_slope_near_vmax"),
            near_c,
            "a slope in (concentric_slope_at_vmax, 1]",
        )?;
        require(
            s.isometric_slope > 1.0,
            &format!("{P}.isometric_slope"),
            s.isometric_slope,
            "a slope > 1",
        )?;
        let e = s.eccentric_slope_at_vmax;
        require(
            at_vmax_ok(e) && e < fmax - 1.0,
            &format!("{P}.eccentric_slope_at_vmax"),
            e,
            "a slope in [0, fmaxE − 1)",
        )?;
        let near_e = s.eccentric_slope_near_vmax;
        let near_e_ok = near_e >= e && near_e < fmax - 1.0;
        require(
            near_e_ok,
            &format!("{P}.eccentric_slope_near_vmax"),
            near_e,
            "a slope in [eccentric_slope_at_vmax, fmaxE − 1)",
        )?;
        check_curviness(&format!("{P}.concentric_curviness"), s.concentric_curviness)?;
        check_curviness(&format!("{P}.eccentric_curviness"), s.eccentric_curviness)
}

/// `createFiberForceVelocityCurve`: normalised fiber velocity (−1 = v_max shortening) →
/// force–velocity multiplier.
pub fn force_velocity(shape: &ForceVelocityCurveSpec) -> Result<SmoothSegmentedFunction, CurveError> {
    check_force_velocity(shape, false)?;
    let s = shape;
    Ok(SmoothSegmentedFunction::new(
        force_velocity_segments(shape)?,
        (-1.0, 0.0, s.concentric_slope_at_vmax),
        (
            1.0,
            s.max_eccentric_velocity_force_multiplier,
            s.eccentric_slope_at_vmax,
        ),
    ))
}

/// `createFiberForceVelocityInverseCurve`: the same corners with x and y exchanged
/// (multiplier → normalised velocity); both end slopes must be positive.
pub fn force_velocity_inverse(
    shape: &ForceVelocityCurveSpec,
) -> Result<SmoothSegmentedFunction, CurveError> {
    check_force_velocity(shape, true)?;
    let s = shape;
    let segments = force_velocity_segments(shape)?
        .iter()
        .map(BezierSegment::transposed)
        .collect();
    Ok(SmoothSegmentedFunction::new(
        segments,
        (0.0, -1.0, 1.0 / s.concentric_slope_at_vmax),
        (
            s.max_eccentric_velocity_force_multiplier,
            1.0,
            1.0 / s.eccentric_slope_at_vmax,
        ),
    ))
}

/// `createFiberForceLengthCurve(eZero, eIso, kLow, kIso, curviness)`: 0 up to 1 + eZero, 1 at
/// 1 + eIso with slope kIso, toe slope kLow.
pub fn fiber_force_length(
    e_zero: f64,
    e_iso: f64,
    k_low: f64,
    k_iso: f64,
    curviness: f64,
) -> Result<SmoothSegmentedFunction, CurveError> {
    const P: &str = "FiberForceLengthCurve";
    require(
        e_iso > e_zero,
        &format!("{P}.strain_at_one_norm_force"),
        e_iso,
        "a strain > strain_at_zero_force",
    )?;
    let k_min = 1.0 / (e_iso - e_zero);
    require(
        k_iso > k_min,
        &format!("{P}.stiffness_at_one_norm_force"),
        k_iso,
        &format!("a stiffness > {k_min}"),
    )?;
    require(
        k_low > 0.0 && k_low < k_min,
        &format!("{P}.stiffness_at_low_force"),
        k_low,
        &format!("a stiffness in (0, {k_min})"),
    )?;
    check_curviness(&format!("{P}.curviness"), curviness)?;
    let c = scale_curviness(curviness);
    let (x_zero, y_zero, x_iso, y_iso) = (1.0 + e_zero, 0.0, 1.0 + e_iso, 1.0);
    let delta_x = (0.1 * (1.0 / k_iso)).min(0.1 * (x_iso - x_zero));
    let x_low = x_zero + delta_x;
    let x_foot = x_zero + 0.5 * (x_low - x_zero);
    let y_low = k_low * (x_low - x_foot);
    let segments = corners(
        &[
            (x_zero, y_zero, 0.0),
            (x_low, y_low, k_low),
            (x_iso, y_iso, k_iso),
        ],
        c,
        P,
    )?;
    Ok(SmoothSegmentedFunction::new(
        segments,
        (x_zero, y_zero, 0.0),
        (x_iso, y_iso, k_iso),
    ))
}

/// `createTendonForceLengthCurve(eIso, kIso, fToe, curviness)`: normalised tendon length
/// 1 + ε → normalised force; toe region up to force fToe, then the line of slope kIso through
/// (1 + eIso, 1).
pub fn tendon_force_length(
    e_iso: f64,
    k_iso: f64,
    f_toe: f64,
    curviness: f64,
) -> Result<SmoothSegmentedFunction, CurveError> {
    const P: &str = "TendonForceLengthCurve";
    require(
        e_iso > 0.0,
        &format!("{P}.strain_at_one_norm_force"),
        e_iso,
        "a strain > 0",
    )?;
    require(
        f_toe > 0.0 && f_toe < 1.0,
        &format!("{P}.norm_force_at_toe_end"),
        f_toe,
        "a force in (0, 1)",
    )?;
    let k_min = 1.0 / e_iso;
    require(
        k_iso > k_min,
        &format!("{P}.stiffness_at_one_norm_force"),
        k_iso,
        &format!("a stiffness > {k_min}"),
    )?;
    check_curviness(&format!("{P}.curviness"), curviness)?;
    let c = scale_curviness(curviness);
    let (x0, y0, dydx0) = (1.0, 0.0, 0.0);
    let (x_iso, y_iso) = (1.0 + e_iso, 1.0);
    let y_toe = f_toe;
    let x_toe = (y_toe - 1.0) / k_iso + x_iso;
    let (x_foot, y_foot) = (1.0 + (x_toe - 1.0) / 10.0, 0.0);
    let y_toe_mid = y_toe * 0.5;
    let x_toe_mid = (y_toe_mid - y_iso) / k_iso + x_iso;
    let dydx_toe_mid = (y_toe_mid - y_foot) / (x_toe_mid - x_foot);
    let x_toe_ctrl = x_foot + 0.5 * (x_toe_mid - x_foot);
    let y_toe_ctrl = y_foot + dydx_toe_mid * (x_toe_ctrl - x_foot);
    let points = [
        (x0, y0, dydx0),
        (x_toe_ctrl, y_toe_ctrl, dydx_toe_mid),
        (x_toe, y_toe, k_iso),
    ];
    let segments = corners(&points, c, P)?;
    Ok(SmoothSegmentedFunction::new(
        segments,
        (x0, y0, dydx0),
        (x_toe, y_toe, k_iso),
    ))
}
