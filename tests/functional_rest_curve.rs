//! A muscle's rest curve at its corner s*, where the clamped branch begins: there every
//! L_ts ≥ L_ts* reproduces the rest fiber length, so the unclamped branch's search for L_ts has
//! no single root; the curve must still be continuous and defined on both sides, and
//! `coordinate_of` must map points to the curve consistently on both branches.

mod common;

use common::fixture;
use osim_tune::io::osim::OsimDocument;
use osim_tune::model::ModelSpec;
use osim_tune::tuning::functional::{DynamometryData, EstimatedMuscles, KneeMomentModel, MuscleParameters, RestCurve, SetSelection, TrialOptions};

/// Calls `check` for every estimated muscle of train01 (set5) whose rest curve from the model's
/// parameters clamps, with the knee model, a workspace, the curve's origin, the curve and its
/// corner (s*, L_ts*); returns how many there were.
fn for_each_clamping_curve(mut check: impl FnMut(&KneeMomentModel, &mut EstimatedMuscles, &MuscleParameters, &RestCurve, (f64, f64))) -> usize {
    let spec = ModelSpec::read(&OsimDocument::read(&fixture("golden/scale/subject01_simbody.osim")).unwrap()).unwrap();
    let data = DynamometryData::read(&fixture("dynamometry/train01"), &TrialOptions { sets: SetSelection::Only(vec!["set5".into()]), ..TrialOptions::default() }).unwrap();
    let knee = KneeMomentModel::new(&spec, &data).unwrap();
    let nominal = knee.nominal_parameters();
    let mut workspace = knee.estimated_muscles(&nominal).unwrap();
    let mut corners = 0;
    for (e, origin) in nominal.iter().enumerate() {
        let reference = data.reference_rest_fiber_length(&origin.name).unwrap();
        let curve = RestCurve::new(&knee, &mut workspace, e, reference, origin).unwrap();
        let Some(corner) = curve.clamp() else { continue };
        corners += 1;
        check(&knee, &mut workspace, origin, &curve, corner);
    }
    corners
}

/// For every estimated muscle of train01 whose rest curve clamps: the points at s* − 10⁻¹²,
/// s* and s* + 10⁻¹² are (L_opt,0·e^(s*), L_ts*) to 10⁻⁹.
#[test]
fn rest_curve_is_continuous_at_its_corner() {
    let corners = for_each_clamping_curve(|knee, workspace, origin, curve, (corner, slack)| {
        for s in [corner - 1e-12, corner, corner + 1e-12] {
            let point = curve.at(knee, workspace, s, origin.tendon_slack_length).unwrap_or_else(|| panic!("{}: no point at s* {s:+e}", origin.name));
            let optimal = origin.optimal_fiber_length * corner.exp();
            assert!((point.optimal_fiber_length / optimal - 1.0).abs() < 1e-9, "{} at s* {s:+e}: L_opt {}, expected {optimal}", origin.name, point.optimal_fiber_length);
            assert!((point.tendon_slack_length / slack - 1.0).abs() < 1e-9, "{} at s* {s:+e}: L_ts {}, expected {slack}", origin.name, point.tendon_slack_length);
        }
    });
    assert!(corners > 0, "no estimated muscle's rest curve clamps");
}

/// `coordinate_of` inverts `at` on both branches, and takes a point whose L_opt is beyond the
/// clamped L_opt* but whose tendon is shorter than L_ts* to the corner (the clamped branch's
/// point nearest in L_ts), not further along the clamped branch.
#[test]
fn coordinate_of_inverts_the_curve_and_meets_short_tendons_at_the_corner() {
    let corners = for_each_clamping_curve(|knee, workspace, origin, curve, (corner, slack)| {
        for s in [corner - 0.05, corner + 0.05] {
            let point = curve.at(knee, workspace, s, origin.tendon_slack_length).unwrap();
            assert!((curve.coordinate_of(&point) - s).abs() < 1e-12, "{}: coordinate of the point at {s}", origin.name);
        }
        let mut short = origin.clone();
        short.optimal_fiber_length = origin.optimal_fiber_length * (corner + 0.05).exp();
        short.tendon_slack_length = 0.95 * slack;
        assert_eq!(curve.coordinate_of(&short), corner, "{}: a short tendon beyond L_opt*", origin.name);
    });
    assert!(corners > 0, "no estimated muscle's rest curve clamps");
}
