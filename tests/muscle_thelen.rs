//! `Thelen2003Muscle` against OpenSim 4.6: the four curves (`fixtures/golden/muscle/<model>/
//! curves.csv`), the static equilibrium along the knee and elbow sweeps (a slice of
//! `equilibrium.csv`: first, middle and last angle of each sweep and the minimum-fiber-length rows
//! of gait2392 `semimem_r`), the fiber-length state derivative
//! (`fixtures/golden/muscle/thelen_velocity/`, from `oracle/gen_thelen_velocity.py`), the
//! equilibrium residual and its uniqueness as properties, and refused input.

mod common;

use std::collections::HashMap;

use osim_tune::io::osim::OsimDocument;
use osim_tune::mechanics::muscle::{
    EquilibriumStatus, FiberEquilibrium, HillMuscle, MuscleError, Thelen2003Muscle,
};
use osim_tune::model::{ModelSpec, MuscleModelSpec, MuscleSpec, ThelenSpec};
use osim_tune::validation::{compare_thelen_curves, compare_thelen_fiber_velocity, GoldenTable};
use proptest::prelude::*;

const MODELS: [(&str, &str); 2] = [
    (
        "gait2392_thelen2003muscle",
        "models/gait2392_thelen2003muscle.osim",
    ),
    ("arm26", "fixtures/models/arm26.osim"),
];

fn model_spec(file: &str) -> ModelSpec {
    ModelSpec::read(&OsimDocument::read(&common::root().join(file)).unwrap())
        .unwrap_or_else(|e| panic!("{e}"))
}

/// Every Thelen2003Muscle of a model by name, built through `HillMuscle::from_force`.
fn thelen_muscles(file: &str) -> HashMap<String, Thelen2003Muscle> {
    model_spec(file)
        .muscles()
        .map(
            |force| match HillMuscle::from_force(force).unwrap_or_else(|e| panic!("{e}")) {
                HillMuscle::Thelen(muscle) => (force.name.clone(), muscle),
                other => panic!("{}: not a Thelen2003Muscle: {other:?}", force.name),
            },
        )
        .collect()
}

fn golden(stem: &str, file: &str) -> GoldenTable {
    GoldenTable::read(&common::fixture(&format!("golden/muscle/{stem}/{file}"))).unwrap()
}

use common::golden_rows::{rows, Row};

/// The largest error of one quantity relative to its tolerance, and where.
#[derive(Default)]
struct Worst {
    error: f64,
    ratio: f64,
    at: String,
}

impl Worst {
    fn record(&mut self, ours: f64, theirs: f64, tolerance: f64, at: impl FnOnce() -> String) {
        let error = (ours - theirs).abs();
        assert!(ours.is_finite(), "not finite: {}", at());
        self.error = self.error.max(error);
        if error / tolerance > self.ratio || self.at.is_empty() {
            self.ratio = error / tolerance;
            self.at = format!(
                "{} (ours {ours}, OpenSim {theirs}, tolerance {tolerance:e})",
                at()
            );
        }
    }

    fn assert_within(&self, what: &str) {
        assert!(
            self.ratio <= 1.0,
            "{what}: off by {:e} at {}",
            self.error,
            self.at
        );
    }
}

/// Every curve sample ≤ 1e-10 absolute (OpenSim's closed-form Thelen formulas sampled through
/// a bench muscle). f_V is checked both ways: f_V(ṽ) against OpenSim's multiplier, and
/// OpenSim's velocity ṽ against ours at its force.
#[test]
fn curves_match_opensim() {
    for (stem, _) in MODELS {
        let c = compare_thelen_curves(&common::fixture(&format!("golden/muscle/{stem}"))).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(c.curves.len(), 4, "{stem}: all four curves");
        assert!(c.velocity.count > 0, "{stem}: the velocity");
        for (what, worst) in [("curve values", &c.value), ("force–velocity inverse", &c.velocity)] {
            assert!(worst.error <= 1e-10, "{stem} {what}: off by {:e} at {}", worst.error, worst.at);
        }
    }
}

/// OpenSim's `getMinimumFiberLength` is the pennation model's (0 for unpennated muscles).
#[test]
fn minimum_fiber_lengths_match_opensim() {
    for (stem, file) in MODELS {
        let muscles = thelen_muscles(file);
        let table = golden(stem, "parameters.csv");
        for row in rows(&table) {
            let muscle = &muscles[row.text("muscle")];
            let expected = row.number("minimum_fiber_length");
            assert!(
                (muscle.minimum_fiber_length() - expected).abs() <= 1e-16,
                "{stem} {}",
                row.text("muscle")
            );
        }
        assert_eq!(muscles.len(), table.rows.len());
    }
}

/// `activation_time_constant` and `deactivation_time_constant` (s) as the file writes them and
/// OpenSim reads them (`parameters.csv`); absent, OpenSim's class defaults 0.015 s and 0.050 s;
/// non-positive, an error naming the file, the muscle and the property.
#[test]
fn time_constants_are_read_as_opensim_reads_them() {
    for (stem, file) in MODELS {
        let text = std::fs::read_to_string(common::root().join(file)).unwrap();
        let muscles = thelen_muscles(file);
        for row in rows(&golden(stem, "parameters.csv")) {
            let muscle = &muscles[row.text("muscle")];
            for (property, ours) in [("activation_time_constant", muscle.activation_time_constant()), ("deactivation_time_constant", muscle.deactivation_time_constant())] {
                assert_eq!(ours, row.number(property), "{stem} {} {property}", muscle.name());
                assert_eq!(ours, property_in_file(&text, muscle.name(), property), "{stem} {} {property}", muscle.name());
            }
        }
    }
    let path = common::root().join("fixtures/models/arm26.osim");
    let text = std::fs::read_to_string(&path).unwrap();
    let read = |edited: String| ModelSpec::read(&OsimDocument::parse(edited, &path).unwrap());
    let first = "<activation_time_constant>0.01</activation_time_constant>";
    let absent = read(text.replacen(first, "", 1).replacen("<deactivation_time_constant>0.040000000000000001</deactivation_time_constant>", "", 1)).unwrap();
    let muscle = |spec: &ModelSpec| match HillMuscle::from_force(spec.muscles().next().unwrap()).unwrap() {
        HillMuscle::Thelen(m) => m,
        other => panic!("{other:?}"),
    };
    assert_eq!((muscle(&absent).activation_time_constant(), muscle(&absent).deactivation_time_constant()), (0.015, 0.050));
    let message = read(text.replacen(first, "<activation_time_constant>0</activation_time_constant>", 1)).unwrap_err().to_string();
    assert!(message.contains("arm26.osim:") && message.contains("TRIlong") && message.contains("<activation_time_constant>"), "{message}");
}

/// The number of property `property` of the Thelen muscle `name` in an .osim file's text.
fn property_in_file(text: &str, name: &str, property: &str) -> f64 {
    let muscle = &text[text.find(&format!("<Thelen2003Muscle name=\"{name}\">")).unwrap()..];
    let muscle = &muscle[..muscle.find("</Thelen2003Muscle>").unwrap()];
    let value = &muscle[muscle.find(&format!("<{property}>")).unwrap() + property.len() + 2..];
    value[..value.find('<').unwrap()].trim().parse().unwrap()
}

/// Worst errors of the equilibrium quantities over a golden table.
#[derive(Default)]
struct EquilibriumComparison {
    quantities: Vec<(&'static str, Worst)>,
    rows: usize,
    clamped_rows: usize,
}

impl EquilibriumComparison {
    fn record(
        &mut self,
        what: &'static str,
        ours: f64,
        theirs: f64,
        tolerance: f64,
        at: &dyn Fn() -> String,
    ) {
        let index = match self.quantities.iter().position(|(name, _)| *name == what) {
            Some(index) => index,
            None => {
                self.quantities.push((what, Worst::default()));
                self.quantities.len() - 1
            }
        };
        self.quantities[index].1.record(ours, theirs, tolerance, at);
    }
}

/// Lengths within 1e-8 m (normalized ones within 1e-8 m / reference length), forces within
/// max(1e-6 N, 1e-8 |F|), multipliers and the pennation angle within what 1e-8 m of fiber length
/// moves them.
///
/// Where OpenSim's own solver tolerance limits agreement: `equilibrateMuscles` stops with
/// |F_m cos α − F_t| < 1e-8 F_max and leaves f_V ≠ 1 (a small fiber velocity), so its state is
/// off the exact static one by the row's imbalance
/// |f_V − 1| · active_fiber_force · cos α + |tendon_force − fiber_force_along_tendon|, which
/// widens the force tolerances of that row (divided by cos α for forces in the fiber's
/// direction). Rows where OpenSim clamps the fiber at its minimum
/// length (fiber forces 0, tendon possibly stretched) are compared without widening.
fn compare_equilibrium(
    muscles: &HashMap<String, Thelen2003Muscle>,
    table: &GoldenTable,
    stem: &str,
) -> EquilibriumComparison {
    let mut comparison = EquilibriumComparison::default();
    for row in rows(table) {
        let name = row.text("muscle");
        let muscle = &muscles[name];
        let (a, mt_length) = (row.number("activation"), row.number("mt_length"));
        let at = || format!("{stem} {} {name} a = {a}", row.text("pose_id"));
        let ours = muscle
            .equilibrium(a, mt_length)
            .unwrap_or_else(|e| panic!("{}: {e}", at()));
        let clamped = row.number("fiber_length") <= muscle.minimum_fiber_length();
        let expected_status = if clamped {
            EquilibriumStatus::ClampedAtMinimumFiberLength
        } else {
            EquilibriumStatus::Converged
        };
        assert_eq!(ours.status, expected_status, "{}", at());
        assert_eq!(
            ours.activation,
            row.number("activation_readback"),
            "{}",
            at()
        );
        let imbalance = if clamped {
            0.0
        } else {
            (row.number("force_velocity_multiplier") - 1.0).abs()
                * row.number("active_fiber_force")
                * row.number("cos_pennation_angle")
                + (row.number("tendon_force") - row.number("fiber_force_along_tendon")).abs()
        };
        record_row(&mut comparison, muscle, &ours, &row, imbalance, &at);
        if !clamped {
            record_opensim_residual(&mut comparison, muscle, &row, &at);
        }
        comparison.rows += 1;
        comparison.clamped_rows += usize::from(clamped);
    }
    comparison
}

const LENGTH_TOLERANCE: f64 = 1e-8;

fn record_row(
    comparison: &mut EquilibriumComparison,
    muscle: &Thelen2003Muscle,
    ours: &FiberEquilibrium,
    row: &Row,
    imbalance: f64,
    at: &dyn Fn() -> String,
) {
    let lengths: [(&str, f64, f64); 6] = [
        ("fiber_length", ours.fiber_length, LENGTH_TOLERANCE),
        (
            "normalized_fiber_length",
            ours.normalized_fiber_length,
            LENGTH_TOLERANCE / muscle.optimal_fiber_length(),
        ),
        (
            "fiber_length_along_tendon",
            ours.fiber_length_along_tendon,
            LENGTH_TOLERANCE,
        ),
        ("tendon_length", ours.tendon_length, LENGTH_TOLERANCE),
        (
            "tendon_strain",
            ours.tendon_strain,
            LENGTH_TOLERANCE / muscle.tendon_slack_length(),
        ),
        ("mt_length", ours.mt_length, 0.0),
    ];
    // 1e-8 m of fiber length moves α by |dα/dL_m| · 1e-8 = tan α / L_m · 1e-8 rad, and the
    // multipliers by their slopes over L_opt.
    let fiber_length = ours.fiber_length;
    let angle_tolerance = LENGTH_TOLERANCE * (ours.pennation_angle.tan() / fiber_length).max(1e-6);
    let curves = muscle.curves();
    let lce_n = ours.normalized_fiber_length;
    let per_length = LENGTH_TOLERANCE / muscle.optimal_fiber_length();
    let multipliers: [(&str, f64, f64); 4] = [
        ("pennation_angle", ours.pennation_angle, angle_tolerance),
        (
            "cos_pennation_angle",
            ours.cos_pennation_angle,
            angle_tolerance,
        ),
        (
            "active_force_length_multiplier",
            ours.active_force_length_multiplier,
            per_length * curves.active_force_length_derivative(lce_n).abs().max(1e-6),
        ),
        (
            "passive_force_multiplier",
            ours.passive_force_multiplier,
            per_length
                * curves
                    .passive_force_length_derivative(lce_n)
                    .abs()
                    .max(1e-6),
        ),
    ];
    for (what, value, tolerance) in lengths.into_iter().chain(multipliers) {
        comparison.record(what, value, row.number(what), tolerance.max(1e-15), at);
    }
    let forces: [(&str, f64); 6] = [
        ("tendon_force", ours.tendon_force),
        ("active_fiber_force", ours.active_fiber_force),
        ("passive_fiber_force", ours.passive_fiber_force),
        ("fiber_force", ours.fiber_force),
        ("fiber_force_along_tendon", ours.fiber_force_along_tendon),
        (
            "tendon_force_minus_fiber_force_along_tendon",
            ours.tendon_force - ours.fiber_force_along_tendon,
        ),
    ];
    for (what, value) in forces {
        let theirs = match what {
            "tendon_force_minus_fiber_force_along_tendon" => {
                row.number("tendon_force") - row.number("fiber_force_along_tendon")
            }
            _ => row.number(what),
        };
        // OpenSim's imbalance is along the tendon; in the fiber's direction it is 1/cos α larger.
        let along_tendon = matches!(what, "tendon_force" | "fiber_force_along_tendon");
        let widening = if along_tendon {
            imbalance
        } else {
            imbalance / ours.cos_pennation_angle
        };
        comparison.record(
            what,
            value,
            theirs,
            (1e-8 * theirs.abs()).max(1e-6) + widening,
            at,
        );
    }
    // Static equilibrium: f_V = 1 and ṽ = 0 exactly; OpenSim's leftovers are within its solver
    // tolerance (|f_V − 1| ≤ 1e-6, |ṽ| ≤ 1e-7).
    comparison.record(
        "force_velocity_multiplier",
        ours.force_velocity_multiplier,
        row.number("force_velocity_multiplier"),
        1e-6,
        at,
    );
    comparison.record(
        "normalized_fiber_velocity",
        ours.normalized_fiber_velocity,
        row.number("normalized_fiber_velocity"),
        1e-7,
        at,
    );
}

/// Our force residual at OpenSim's fiber length is OpenSim's own leftover: its tendon force
/// balances a f_L f_V F_max + f_PE F_max with f_V ≠ 1, so r = (1 − f_V) a f_L F_max cos α. This
/// shows the differences above come from OpenSim's stopping point, not from the curves.
fn record_opensim_residual(
    comparison: &mut EquilibriumComparison,
    muscle: &Thelen2003Muscle,
    row: &Row,
    at: &dyn Fn() -> String,
) {
    let (a, mt_length) = (row.number("activation"), row.number("mt_length"));
    let ours = muscle.static_force_residual(a, row.number("fiber_length"), mt_length);
    let fv = row.number("force_velocity_multiplier");
    let theirs =
        (1.0 - fv) * row.number("active_fiber_force") / fv * row.number("cos_pennation_angle");
    comparison.record("residual_at_opensim_fiber_length", ours, theirs, 1e-10, at);
}

#[test]
fn equilibrium_matches_opensim() {
    for (stem, file) in MODELS {
        let muscles = thelen_muscles(file);
        let table = golden(stem, "equilibrium.csv");
        let comparison = compare_equilibrium(&muscles, &table, stem);
        for (what, worst) in &comparison.quantities {
            worst.assert_within(&format!("{stem} {what}"));
        }
        assert_eq!(comparison.quantities.len(), 19, "{stem}");
        let expected = if stem == "arm26" { (144, 0) } else { (316, 7) };
        assert_eq!(
            (comparison.rows, comparison.clamped_rows),
            expected,
            "{stem}"
        );
    }
}

/// The Thelen quirk, reproduced: gait2392 `semimem_r` at `knee_h00_k-080` with a ≥ 0.5 would
/// need a fiber shorter than its minimum, so OpenSim clamps it there and reports zero fiber
/// force while the tendon is stretched (3.81 N). At a = 0.05 the fiber balances just above the
/// minimum.
#[test]
fn semimem_at_knee_flexion_reproduces_the_minimum_fiber_length_clamp() {
    let muscles = thelen_muscles("models/gait2392_thelen2003muscle.osim");
    let semimem = &muscles["semimem_r"];
    let table = golden("gait2392_thelen2003muscle", "equilibrium.csv");
    let rows: Vec<Row> = rows(&table)
        .filter(|r| r.text("pose_id") == "knee_h00_k-080" && r.text("muscle") == "semimem_r")
        .collect();
    assert_eq!(rows.len(), 4);
    for row in rows {
        let ours = semimem
            .equilibrium(row.number("activation"), row.number("mt_length"))
            .unwrap();
        let clamped = row.number("activation") >= 0.5;
        assert_eq!(
            ours.status == EquilibriumStatus::ClampedAtMinimumFiberLength,
            clamped
        );
        if clamped {
            assert_eq!(ours.fiber_length, semimem.minimum_fiber_length());
            assert_eq!(
                ours.pennation_angle,
                semimem.pennation().maximum_pennation_angle
            );
            assert_eq!(
                (
                    ours.fiber_force,
                    ours.active_fiber_force,
                    ours.fiber_force_along_tendon
                ),
                (0.0, 0.0, 0.0)
            );
            assert!(
                (ours.tendon_force - row.number("tendon_force")).abs() < 1e-9,
                "{}",
                ours.tendon_force
            );
            assert!(ours.tendon_force > 3.8);
            assert!(
                semimem.static_force_residual(
                    row.number("activation"),
                    ours.fiber_length,
                    ours.mt_length
                ) > 0.0
            );
        }
    }
}

/// Slack: a path shorter than L_ts + L_min cos α_max leaves the tendon slack at the minimum fiber
/// length; every force is 0 and nothing is NaN. Unpennated muscles (minimum length 0) too.
#[test]
fn a_slack_path_gives_zero_force_at_the_minimum_fiber_length() {
    for (file, name) in [
        ("models/gait2392_thelen2003muscle.osim", "semimem_r"),
        ("fixtures/models/arm26.osim", "BIClong"),
    ] {
        let muscles = thelen_muscles(file);
        let muscle = &muscles[name];
        let mt_length = 0.9 * muscle.tendon_slack_length();
        for a in [0.0, 0.5, 1.0] {
            let e = muscle.equilibrium(a, mt_length).unwrap();
            assert_eq!(
                e.status,
                EquilibriumStatus::ClampedAtMinimumFiberLength,
                "{name}"
            );
            assert_eq!(e.fiber_length, muscle.minimum_fiber_length());
            assert_eq!(
                (e.tendon_force, e.fiber_force, e.passive_fiber_force),
                (0.0, 0.0, 0.0),
                "{name}"
            );
            assert_all_finite(&e);
        }
    }
}

fn assert_all_finite(e: &FiberEquilibrium) {
    let values = [
        e.activation,
        e.mt_length,
        e.fiber_length,
        e.normalized_fiber_length,
        e.pennation_angle,
        e.cos_pennation_angle,
        e.fiber_length_along_tendon,
        e.tendon_length,
        e.tendon_strain,
        e.tendon_force,
        e.active_fiber_force,
        e.passive_fiber_force,
        e.fiber_force,
        e.fiber_force_along_tendon,
        e.active_force_length_multiplier,
        e.passive_force_multiplier,
        e.force_velocity_multiplier,
        e.normalized_fiber_velocity,
    ];
    assert!(values.iter().all(|v| v.is_finite()), "{e:?}");
}

/// The state derivative dL_m/dt against OpenSim's (`getStateVariableDerivativeValue`) on a
/// grid of activations (0 clamped to 0.01), fiber lengths (below, at and above the minimum)
/// and tendon strains (slack to linear region): ≤ 1e-9 relative, 1e-12 m/s absolute.
#[test]
fn fiber_velocity_matches_opensim() {
    let specs: Vec<(&str, ModelSpec)> = MODELS.iter().map(|(stem, file)| (*stem, model_spec(file))).collect();
    let models: Vec<(&str, &ModelSpec)> = specs.iter().map(|(stem, spec)| (*stem, spec)).collect();
    let worst = compare_thelen_fiber_velocity(&models, &common::fixture("golden/muscle/thelen_velocity")).unwrap_or_else(|e| panic!("{e}"));
    assert!(worst.error <= 1e-9, "fiber velocity: off by {:e} relative at {}", worst.error, worst.at);
    assert_eq!(worst.count, 396);
}

/// At the static equilibrium the state derivative vanishes (|dL_m/dt| ≤ 1e-8 m/s: the residual
/// ≤ 1e-9 N through the slope of ṽ(F)); a longer fiber shortens back, a shorter one lengthens.
#[test]
fn fiber_velocity_vanishes_at_equilibrium_and_restores_it() {
    let muscles = thelen_muscles("models/gait2392_thelen2003muscle.osim");
    for name in ["rect_fem_r", "vas_int_r", "med_gas_r", "bifemsh_r"] {
        let muscle = &muscles[name];
        let mt_length = muscle.tendon_slack_length() * 1.01 + muscle.optimal_fiber_length();
        for a in [0.05, 0.5, 1.0] {
            let e = muscle.equilibrium(a, mt_length).unwrap();
            assert_eq!(e.status, EquilibriumStatus::Converged);
            let at_rest = muscle.fiber_velocity(a, e.fiber_length, mt_length).unwrap();
            assert!(at_rest.abs() <= 1e-8, "{name} a = {a}: {at_rest}");
            let step = 1e-3 * muscle.optimal_fiber_length();
            assert!(
                muscle
                    .fiber_velocity(a, e.fiber_length + step, mt_length)
                    .unwrap()
                    < 0.0,
                "{name} a = {a}"
            );
            assert!(
                muscle
                    .fiber_velocity(a, e.fiber_length - step, mt_length)
                    .unwrap()
                    > 0.0,
                "{name} a = {a}"
            );
        }
    }
}

/// Every Thelen muscle of gait2392 and arm26, for the property test.
fn all_muscles() -> Vec<Thelen2003Muscle> {
    let mut all: Vec<Thelen2003Muscle> = MODELS
        .iter()
        .flat_map(|(_, file)| thelen_muscles(file).into_values())
        .collect();
    all.sort_by(|a, b| a.name().cmp(b.name()));
    all
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 2000, ..ProptestConfig::default() })]

    /// For random muscles, activations and path lengths from slack (0.9 L_ts) to a fiber at
    /// 1.8 L_opt on a 6 % strained tendon: |r| ≤ 1e-9 N at a converged equilibrium; r(L_min) > 0
    /// when clamped. Uniqueness: sampled on 400 fiber lengths of [L_min, L_mt − L_ts + h], r < 0
    /// below the solution and > 0 above it (outside 1e-9 m of it).
    #[test]
    fn equilibrium_is_the_unique_zero_of_the_residual(index in 0usize..98, a in 0.0f64..=1.0, u in 0.0f64..=1.0) {
        let muscles = all_muscles_cached();
        let muscle = &muscles[index % muscles.len()];
        let shortest = 0.9 * muscle.tendon_slack_length();
        let longest = 1.06 * muscle.tendon_slack_length() + 1.8 * muscle.optimal_fiber_length();
        let mt_length = shortest + u * (longest - shortest);
        let e = muscle.equilibrium(a, mt_length).unwrap();
        assert_all_finite(&e);
        let residual = |l: f64| muscle.static_force_residual(a, l, mt_length);
        match e.status {
            EquilibriumStatus::Converged => prop_assert!(residual(e.fiber_length).abs() <= 1e-9, "{}", residual(e.fiber_length)),
            EquilibriumStatus::ClampedAtMinimumFiberLength => prop_assert!(residual(muscle.minimum_fiber_length()) > 0.0),
        }
        let lo = muscle.minimum_fiber_length();
        let hi = (mt_length - muscle.tendon_slack_length()).max(lo) + muscle.pennation().parallelogram_height;
        for i in 0..=400 {
            let l = lo + (hi - lo) * f64::from(i) / 400.0;
            if (l - e.fiber_length).abs() > 1e-9 {
                let r = residual(l);
                prop_assert!(if l < e.fiber_length { r < 0.0 } else { r > 0.0 }, "{} a = {a} L_mt = {mt_length}: r({l}) = {r}, solution {}", muscle.name(), e.fiber_length);
            }
        }
    }
}

fn all_muscles_cached() -> &'static [Thelen2003Muscle] {
    static MUSCLES: std::sync::OnceLock<Vec<Thelen2003Muscle>> = std::sync::OnceLock::new();
    MUSCLES.get_or_init(all_muscles)
}

fn semimem_spec() -> (MuscleSpec, ThelenSpec) {
    let spec = model_spec("models/gait2392_thelen2003muscle.osim");
    let muscle = spec
        .muscles()
        .find(|f| f.name == "semimem_r")
        .unwrap()
        .muscle
        .clone()
        .unwrap();
    let MuscleModelSpec::Thelen2003(class) = muscle.model.clone() else {
        panic!("not Thelen")
    };
    (muscle, class)
}

#[test]
fn bad_input_is_refused() {
    let muscles = thelen_muscles("models/gait2392_thelen2003muscle.osim");
    let muscle = &muscles["semimem_r"];
    for (a, mt_length) in [
        (-0.1, 0.4),
        (1.1, 0.4),
        (f64::NAN, 0.4),
        (0.5, 0.0),
        (0.5, -1.0),
        (0.5, f64::NAN),
        (0.5, f64::INFINITY),
    ] {
        assert!(
            matches!(
                muscle.equilibrium(a, mt_length),
                Err(MuscleError::InvalidInput { .. })
            ),
            "a {a} L_mt {mt_length}"
        );
        assert!(matches!(
            muscle.fiber_velocity(a, 0.08, mt_length),
            Err(MuscleError::InvalidInput { .. })
        ));
    }
    for fiber_length in [-0.01, f64::NAN, f64::INFINITY] {
        assert!(matches!(
            muscle.fiber_velocity(0.5, fiber_length, 0.4),
            Err(MuscleError::InvalidInput { .. })
        ));
    }
}

/// A property name and an edit making it invalid.
type ClassInvalidation = (&'static str, fn(&mut ThelenSpec));
type SpecInvalidation = (&'static str, fn(&mut MuscleSpec));

/// What `Thelen2003Muscle::extendFinalizeFromProperties` and its pennation and activation
/// models throw on, plus the two flags OpenSim does not implement for this class.
#[test]
fn parameters_opensim_rejects_are_refused() {
    let class_edits: [ClassInvalidation; 12] = [
        ("FmaxTendonStrain", |c| c.fmax_tendon_strain = 0.0),
        ("FmaxMuscleStrain", |c| c.fmax_muscle_strain = -1.0),
        ("KshapeActive", |c| c.kshape_active = 0.0),
        ("KshapePassive", |c| c.kshape_passive = 0.0),
        ("Af", |c| c.af = -0.3),
        ("Flen", |c| c.flen = 0.9),
        ("fv_linear_extrap_threshold", |c| {
            c.fv_linear_extrap_threshold = 0.5
        }),
        ("maximum_pennation_angle", |c| {
            c.maximum_pennation_angle = 2.0
        }),
        ("minimum_activation", |c| c.minimum_activation = 0.005),
        ("minimum_activation", |c| c.minimum_activation = 1.0),
        ("activation_time_constant", |c| c.activation_time_constant = 0.0),
        ("deactivation_time_constant", |c| c.deactivation_time_constant = -0.05),
    ];
    let spec_edits: [SpecInvalidation; 4] = [
        ("ignore_tendon_compliance", |s| {
            s.ignore_tendon_compliance = true
        }),
        ("ignore_activation_dynamics", |s| {
            s.ignore_activation_dynamics = true
        }),
        ("pennation_angle_at_optimal", |s| {
            s.pennation_angle_at_optimal = std::f64::consts::FRAC_PI_2
        }),
        ("max_isometric_force", |s| s.max_isometric_force = 0.0),
    ];
    let refused =
        |property: &str, spec: &MuscleSpec, class: &ThelenSpec| match Thelen2003Muscle::new(
            "semimem_r",
            spec,
            class,
        ) {
            Err(MuscleError::InvalidParameter { property: p, .. }) => assert_eq!(p, property),
            other => panic!("{property}: {other:?}"),
        };
    for (property, edit) in class_edits {
        let (spec, mut class) = semimem_spec();
        edit(&mut class);
        refused(property, &spec, &class);
    }
    for (property, edit) in spec_edits {
        let (mut spec, class) = semimem_spec();
        edit(&mut spec);
        refused(property, &spec, &class);
    }
}
