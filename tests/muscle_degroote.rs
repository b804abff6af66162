//! `DeGrooteFregly2016Muscle` against OpenSim 4.6's own numbers (`fixtures/golden/muscle/degroote/`,
//! written by `oracle/gen_degroote.py` from `fixtures/models/degroote_bench.osim`), a property
//! test of the equilibrium, and the inputs and parameters it refuses.
//!
//! Bounds against the goldens:
//! - curves: |Δ| ≤ 1e-12 · max(1, |y|) for values and derivatives (the functions are the same
//!   closed forms in the same operation order; the brief's 1e-10 absolute is looser);
//! - equilibrium: lengths ≤ 1e-8 m, tendon force ≤ max(1e-6 N, 1e-8 |F_T|). OpenSim's bisection
//!   stops within 1e-10 of the normalized tendon force, ≤ 1e-10 · 5000 N = 5e-7 N here, so the
//!   tendon force needs no widening. OpenSim's getters then evaluate the explicit model at that
//!   slightly unbalanced state, which shows up as a fiber velocity ṽ ≠ 0 (|ṽ| ≤ 1e-6): its active,
//!   damping and fiber forces carry F_max (a f_L |f_V(ṽ) − f_V(0)| + β |ṽ|) — the row's own
//!   imbalance — which widens the bound on those forces row by row. Rows where OpenSim threw, and
//!   the rigid tendon below its slack length (OpenSim reports a backwards fiber), must be
//!   `Infeasible` here;
//! - fiber velocity: |Δ| ≤ 1e-9 · max(1 m/s, |v|).

mod common;

use std::collections::HashMap;

use osim_tune::io::osim::OsimDocument;
use osim_tune::mechanics::muscle::{DeGrooteCurves, DeGrooteFregly2016Muscle, HillMuscle, MuscleError};
use osim_tune::model::{DeGrooteSpec, ModelSpec, MuscleModelSpec, MuscleSpec};
use osim_tune::validation::{compare_degroote_curves, compare_degroote_equilibrium, compare_degroote_fiber_velocity, GoldenTable, DEGROOTE_LENGTH_TOLERANCE};
use proptest::prelude::*;

fn golden(file: &str) -> GoldenTable {
    GoldenTable::read(&golden_folder().join(file)).unwrap()
}

use common::golden_rows::rows;

fn bench_model() -> ModelSpec {
    ModelSpec::read(&OsimDocument::read(&common::fixture("models/degroote_bench.osim")).unwrap()).unwrap()
}

/// The bench model's muscle specifications, as read from the .osim file.
fn bench_muscles() -> HashMap<String, (MuscleSpec, DeGrooteSpec)> {
    bench_model()
        .muscles()
        .map(|force| {
            let muscle = force.muscle.clone().unwrap();
            let MuscleModelSpec::DeGrooteFregly2016(class) = muscle.model.clone() else { panic!("{}", force.name) };
            assert!(matches!(HillMuscle::from_force(force), Ok(HillMuscle::DeGroote(_))));
            (force.name.clone(), (muscle, class))
        })
        .collect()
}

fn golden_folder() -> std::path::PathBuf {
    common::fixture("golden/muscle/degroote")
}

#[test]
fn the_bench_model_reads_as_opensim_wrote_it() {
    let muscles = bench_muscles();
    let parameters = golden("parameters.csv");
    assert_eq!(muscles.len(), parameters.rows.len());
    for row in rows(&parameters) {
        let (spec, class) = &muscles[row.text("muscle")];
        let numbers = [
            ("max_isometric_force", spec.max_isometric_force),
            ("optimal_fiber_length", spec.optimal_fiber_length),
            ("tendon_slack_length", spec.tendon_slack_length),
            (
                "pennation_angle_at_optimal",
                spec.pennation_angle_at_optimal,
            ),
            ("max_contraction_velocity", spec.max_contraction_velocity),
            ("active_force_width_scale", class.active_force_width_scale),
            ("fiber_damping", class.fiber_damping),
            (
                "passive_fiber_strain_at_one_norm_force",
                class.passive_fiber_strain_at_one_norm_force,
            ),
            (
                "tendon_strain_at_one_norm_force",
                class.tendon_strain_at_one_norm_force,
            ),
        ];
        for (column, value) in numbers {
            assert_eq!(value, row.number(column), "{} {column}", row.text("muscle"));
        }
        assert_eq!(
            spec.ignore_tendon_compliance,
            row.text("ignore_tendon_compliance") == "1"
        );
        assert_eq!(
            class.ignore_passive_fiber_force,
            row.text("ignore_passive_fiber_force") == "1"
        );
        assert_eq!(
            class.tendon_compliance_dynamics_mode,
            row.text("tendon_compliance_dynamics_mode")
        );
    }
}

/// `activation_time_constant` and `deactivation_time_constant` (s): OpenSim's class defaults
/// 0.015 s and 0.060 s where the bench model leaves them out, the file's values where it gives
/// them, and an error naming the file, the muscle and the property for a non-positive or
/// non-numeric one.
#[test]
fn time_constants_are_read_with_opensim_defaults() {
    let path = common::fixture("models/degroote_bench.osim");
    let text = std::fs::read_to_string(&path).unwrap();
    let muscle = "<DeGrooteFregly2016Muscle name=\"pennate\">";
    assert!(text.contains(muscle) && !text.contains("time_constant"));
    let with = |properties: &str| {
        let edited = text.replacen(muscle, &format!("{muscle}\n{properties}"), 1);
        ModelSpec::read(&OsimDocument::parse(edited, &path).unwrap())
    };
    let given = "<activation_time_constant> 0.02 </activation_time_constant><deactivation_time_constant>0.075</deactivation_time_constant>";
    let spec = with(given).unwrap();
    let time_constants = |name: &str| match HillMuscle::from_force(spec.muscles().find(|f| f.name == name).unwrap()).unwrap() {
        HillMuscle::DeGroote(m) => (m.activation_time_constant(), m.deactivation_time_constant()),
        other => panic!("{other:?}"),
    };
    assert_eq!(time_constants("pennate"), (0.02, 0.075));
    assert_eq!(time_constants("default"), (0.015, 0.060));
    for (bad, property) in [
        ("<activation_time_constant>0</activation_time_constant>", "activation_time_constant"),
        ("<deactivation_time_constant>-0.06</deactivation_time_constant>", "deactivation_time_constant"),
        ("<deactivation_time_constant>fast</deactivation_time_constant>", "deactivation_time_constant"),
    ] {
        let message = with(bad).unwrap_err().to_string();
        assert!(message.contains("degroote_bench.osim:") && message.contains("pennate") && message.contains(&format!("<{property}>")), "{message}");
    }
}

#[test]
fn curves_agree_with_opensim() {
    let c = compare_degroote_curves(&golden_folder()).unwrap_or_else(|e| panic!("{e}"));
    for (what, worst) in [("value", &c.value), ("derivative", &c.derivative)] {
        assert!(worst.error <= 1e-12, "{what}: |Δ| / max(1, |y|) = {:e} at {}", worst.error, worst.at);
    }
    assert_eq!(c.value.count, 772);
    println!("curves: worst |Δ| / max(1, |y|) {:e}, derivatives {:e}", c.value.error, c.derivative.error);
}

#[test]
fn equilibrium_agrees_with_opensim() {
    let c = compare_degroote_equilibrium(&bench_model(), &golden_folder()).unwrap_or_else(|e| panic!("{e}"));
    assert!(c.mismatches.is_empty(), "{:#?}", c.mismatches);
    assert!(c.lengths.error <= DEGROOTE_LENGTH_TOLERANCE, "lengths: |Δ| = {:e} at {}", c.lengths.error, c.lengths.at);
    for (what, worst) in [("tendon force", &c.tendon_force), ("fiber forces", &c.fiber_forces)] {
        assert!(worst.error <= 1.0, "{what}: {:e} of the allowance at {}", worst.error, worst.at);
    }
    assert_eq!((c.compared, c.refused), (404, 76));
    println!("equilibrium worst: {c:#?}");
}

#[test]
fn fiber_velocity_agrees_with_opensim() {
    let worst = compare_degroote_fiber_velocity(&bench_model(), &golden_folder()).unwrap_or_else(|e| panic!("{e}"));
    assert!(worst.error <= 1e-9, "fiber velocity: |Δ| / max(1, |v|) = {:e} at {}", worst.error, worst.at);
    assert_eq!(worst.count, 243);
    println!("fiber velocity: worst |Δ| / max(1, |v|) {:e}", worst.error);
}

// ---------------------------------------------------------------------------------------
// Properties of the equilibrium
// ---------------------------------------------------------------------------------------

fn spec(
    (max_isometric_force, optimal_fiber_length, tendon_slack_length, pennation_angle_at_optimal): (
        f64,
        f64,
        f64,
        f64,
    ),
    class: DeGrooteSpec,
) -> MuscleSpec {
    MuscleSpec {
        max_isometric_force,
        optimal_fiber_length,
        tendon_slack_length,
        pennation_angle_at_optimal,
        max_contraction_velocity: 10.0,
        ignore_tendon_compliance: false,
        ignore_activation_dynamics: false,
        model: MuscleModelSpec::DeGrooteFregly2016(class),
    }
}

fn class(active_force_width_scale: f64, passive_strain: f64, tendon_strain: f64) -> DeGrooteSpec {
    DeGrooteSpec {
        active_force_width_scale,
        fiber_damping: 0.0,
        ignore_passive_fiber_force: false,
        passive_fiber_strain_at_one_norm_force: passive_strain,
        tendon_strain_at_one_norm_force: tendon_strain,
        default_activation: 0.5,
        default_normalized_tendon_force: 0.5,
        tendon_compliance_dynamics_mode: "explicit".into(),
        activation_time_constant: 0.015,
        deactivation_time_constant: 0.060,
        activation_dynamics_smoothing: 0.1,
    }
}

fn muscle(architecture: (f64, f64, f64, f64), class: DeGrooteSpec) -> DeGrooteFregly2016Muscle {
    DeGrooteFregly2016Muscle::new("property", &spec(architecture, class.clone()), &class).unwrap()
}

/// (fiber length, residual) at 200 normalized tendon forces evenly over the equilibrium
/// bracket [0, min(5, f_T(L_mt / L_ts))], tendon force increasing (fiber length decreasing).
fn sampled_residual(
    muscle: &DeGrooteFregly2016Muscle,
    activation: f64,
    mt_length: f64,
    tendon_slack_length: f64,
) -> Vec<(f64, f64)> {
    let curves = muscle.curves();
    let upper = curves
        .calc_tendon_force_multiplier(mt_length / tendon_slack_length)
        .min(DeGrooteCurves::MAX_NORMALIZED_TENDON_FORCE);
    let width = muscle.fiber_width();
    (0..200)
        .map(|k| {
            let force = upper * k as f64 / 199.0;
            let along_tendon = mt_length
                - tendon_slack_length * curves.calc_tendon_force_length_inverse_curve(force);
            (
                (along_tendon * along_tendon + width * width).sqrt(),
                muscle.calc_equilibrium_residual(activation, mt_length, force),
            )
        })
        .collect()
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 2000,
        rng_seed: proptest::test_runner::RngSeed::Fixed(20261121),
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    /// Muscles with tendons up to 6 optimal fiber lengths long (the bench's longest is 8), path
    /// lengths from just above L_ts to a fiber stretched past 1.6 L_opt. The equilibrium
    /// balances fiber and tendon within 1e-9 N and is the only one: the residual sampled over the
    /// bracket changes sign exactly once (never when the path is refused). Where the tendon at
    /// its softest (df_T/dl̃_T = 0.2 k_T, at f̃_T = 0) is stiffer than the steepest descending
    /// active limb (df_L/dl̃_m = −2.174 / active_force_width_scale, scaled by L_ts / L_opt), the
    /// residual is moreover strictly monotone in the fiber length over the whole bracket. (With
    /// softer tendons OpenSim's residual dips away from the root — r' < 0 on the descending limb
    /// at low tendon force — while the root stays unique; OpenSim's bisection and the Newton
    /// solve then agree on it.)
    #[test]
    fn equilibrium_is_balanced_and_unique(
        max_isometric_force in 100.0..5000.0f64,
        optimal_fiber_length in 0.03..0.15f64,
        tendon_to_fiber in 0.2..6.0f64,
        pennation_angle_at_optimal in 0.0..0.5f64,
        width_scale in 1.0..2.0f64,
        passive_strain in 0.3..1.0f64,
        tendon_strain in 0.02..0.06f64,
        activation in 0.0..=1.0f64,
        stretch in 0.01..1.0f64,
    ) {
        let tendon_slack_length = tendon_to_fiber * optimal_fiber_length;
        let architecture = (max_isometric_force, optimal_fiber_length, tendon_slack_length, pennation_angle_at_optimal);
        let muscle = muscle(architecture, class(width_scale, passive_strain, tendon_strain));
        let mt_length = tendon_slack_length + stretch * (tendon_slack_length * tendon_strain + 1.6 * optimal_fiber_length);
        let equilibrium = muscle.equilibrium(activation, mt_length);
        match &equilibrium {
            Ok(eq) => {
                prop_assert!((eq.tendon_force - eq.fiber_force_along_tendon).abs() <= 1e-9, "{eq:?}");
                prop_assert!(eq.fiber_length.is_finite() && eq.tendon_force >= 0.0);
            }
            Err(error) => prop_assert!(matches!(error, MuscleError::Infeasible { .. }), "{error}"),
        }
        let samples = sampled_residual(&muscle, activation, mt_length, tendon_slack_length);
        let sign_changes = samples.windows(2).filter(|pair| (pair[0].1 > 0.0) != (pair[1].1 > 0.0)).count();
        prop_assert_eq!(sign_changes, usize::from(equilibrium.is_ok()));
        let steepest_active_limb = 2.174 / width_scale * tendon_to_fiber;
        if steepest_active_limb < 0.2 * muscle.curves().tendon_stiffness_parameter() {
            for pair in samples.windows(2) {
                let ((longer, before), (shorter, after)) = (pair[0], pair[1]);
                prop_assert!(shorter < longer, "fiber length not decreasing: {shorter} ≥ {longer}");
                prop_assert!(after > before, "residual not monotone at fiber length {shorter}: {after} ≤ {before}");
            }
        }
    }
}

// ---------------------------------------------------------------------------------------
// Refused inputs and parameters, edge behaviour
// ---------------------------------------------------------------------------------------

const DEFAULT_ARCHITECTURE: (f64, f64, f64, f64) = (1000.0, 0.1, 0.2, 0.2);

fn default_class() -> DeGrooteSpec {
    class(1.0, 0.6, 0.049)
}

#[test]
fn bad_inputs_are_invalid_input() {
    let muscle = muscle(DEFAULT_ARCHITECTURE, default_class());
    for activation in [-0.01, 1.01, f64::NAN, f64::INFINITY] {
        assert!(
            matches!(
                muscle.equilibrium(activation, 0.3),
                Err(MuscleError::InvalidInput { .. })
            ),
            "{activation}"
        );
        assert!(matches!(
            muscle.fiber_velocity(activation, 0.1, 0.3),
            Err(MuscleError::InvalidInput { .. })
        ));
    }
    for mt_length in [0.0, -0.3, f64::NAN, f64::INFINITY] {
        assert!(
            matches!(
                muscle.equilibrium(0.5, mt_length),
                Err(MuscleError::InvalidInput { .. })
            ),
            "{mt_length}"
        );
        assert!(matches!(
            muscle.fiber_velocity(0.5, 0.1, mt_length),
            Err(MuscleError::InvalidInput { .. })
        ));
    }
    let width = muscle.fiber_width();
    for fiber_length in [width, 0.5 * width, 0.0, f64::NAN] {
        assert!(
            matches!(
                muscle.fiber_velocity(0.5, fiber_length, 0.3),
                Err(MuscleError::InvalidInput { .. })
            ),
            "{fiber_length}"
        );
    }
}

#[test]
fn parameters_opensim_rejects_are_invalid_parameter() {
    let rejects = |property: &str, change: &dyn Fn(&mut MuscleSpec, &mut DeGrooteSpec)| {
        let mut class = default_class();
        let mut spec = spec(DEFAULT_ARCHITECTURE, class.clone());
        change(&mut spec, &mut class);
        match DeGrooteFregly2016Muscle::new("bad", &spec, &class) {
            Err(MuscleError::InvalidParameter {
                property: reported, ..
            }) => assert_eq!(reported, property),
            other => panic!("{property}: {other:?}"),
        }
    };
    rejects("active_force_width_scale", &|_, c| {
        c.active_force_width_scale = 0.99
    });
    rejects("active_force_width_scale", &|_, c| {
        c.active_force_width_scale = f64::NAN
    });
    rejects("fiber_damping", &|_, c| c.fiber_damping = -1e-3);
    rejects("passive_fiber_strain_at_one_norm_force", &|_, c| {
        c.passive_fiber_strain_at_one_norm_force = 0.0
    });
    rejects("tendon_strain_at_one_norm_force", &|_, c| {
        c.tendon_strain_at_one_norm_force = -0.049
    });
    rejects("default_activation", &|_, c| c.default_activation = 0.0);
    rejects("activation_time_constant", &|_, c| c.activation_time_constant = 0.0);
    rejects("deactivation_time_constant", &|_, c| c.deactivation_time_constant = f64::NAN);
    rejects("default_normalized_tendon_force", &|_, c| {
        c.default_normalized_tendon_force = 5.01
    });
    rejects("default_normalized_tendon_force", &|_, c| {
        c.default_normalized_tendon_force = -0.1
    });
    rejects("pennation_angle_at_optimal", &|s, _| {
        s.pennation_angle_at_optimal = std::f64::consts::FRAC_PI_2
    });
    rejects("pennation_angle_at_optimal", &|s, _| {
        s.pennation_angle_at_optimal = -0.1
    });
    rejects("optimal_fiber_length", &|s, _| s.optimal_fiber_length = 0.0);
    rejects("tendon_slack_length", &|s, _| {
        s.tendon_slack_length = f64::NAN
    });
}

#[test]
fn paths_without_equilibrium_are_infeasible() {
    let unpennated = muscle((1000.0, 0.1, 0.2, 0.0), default_class());
    let infeasible =
        |activation: f64, mt_length: f64| match unpennated.equilibrium(activation, mt_length) {
            Err(MuscleError::Infeasible { reason, .. }) => reason,
            other => panic!("a = {activation}, L_mt = {mt_length}: {other:?}"),
        };
    // Shorter than the tendon slack length: the fiber would point backwards.
    assert!(infeasible(0.5, 0.2).contains("tendon_slack_length"));
    // Fiber at 0.05 L_opt with no activation: the passive element pushes (f_PE < 0).
    assert!(infeasible(0.0, 0.205).contains("too short"));
    // Fiber beyond 2.2 L_opt: more than 5 F_max of passive force.
    assert!(infeasible(0.3, 0.2 * 1.049 + 0.25).contains("too long"));
    // 10 µm beyond L_ts, the unpennated fiber (0.18 % of F_max at zero length) outpulls the
    // tendon at every length: the balance jumps where the fiber length reaches 0.
    assert!(infeasible(1.0, 0.2 + 1e-5).contains("zero length"));
    // A pennate fiber turns across the tendon instead (cos α → 0) and balances it.
    let pennate = muscle((1000.0, 0.1, 0.2, 0.2), default_class())
        .equilibrium(1.0, 0.2 + 1e-5)
        .unwrap();
    assert!(
        pennate.cos_pennation_angle > 0.0
            && (pennate.tendon_force - pennate.fiber_force_along_tendon).abs() < 1e-9
    );
}

#[test]
fn a_muscle_without_force_sits_at_tendon_slack_length() {
    let mut silent = default_class();
    silent.ignore_passive_fiber_force = true;
    let eq = muscle(DEFAULT_ARCHITECTURE, silent)
        .equilibrium(0.0, 0.33)
        .unwrap();
    assert_eq!(
        (eq.tendon_force, eq.fiber_force, eq.tendon_length),
        (0.0, 0.0, 0.2)
    );
    assert!((eq.fiber_length_along_tendon - 0.13).abs() < 1e-15);
}

#[test]
fn a_rigid_tendon_keeps_its_slack_length_and_has_no_fiber_state() {
    let class = default_class();
    let mut rigid = spec(DEFAULT_ARCHITECTURE, class.clone());
    rigid.ignore_tendon_compliance = true;
    let muscle = DeGrooteFregly2016Muscle::new("rigid", &rigid, &class).unwrap();
    let eq = muscle.equilibrium(0.7, 0.31).unwrap();
    assert_eq!((eq.tendon_length, eq.tendon_strain), (0.2, 0.0));
    assert_eq!(eq.tendon_force, eq.fiber_force_along_tendon);
    assert!(matches!(
        muscle.fiber_velocity(0.7, eq.fiber_length, 0.31),
        Err(MuscleError::InvalidInput { .. })
    ));
}

#[test]
fn fiber_velocity_vanishes_at_equilibrium_and_needs_activation_or_damping() {
    let explicit = muscle(DEFAULT_ARCHITECTURE, default_class());
    let eq = explicit.equilibrium(0.6, 0.29).unwrap();
    assert!(
        explicit
            .fiber_velocity(0.6, eq.fiber_length, 0.29)
            .unwrap()
            .abs()
            < 1e-12
    );
    // A stretched tendon and no active force: no velocity balances it without damping …
    assert!(matches!(
        explicit.fiber_velocity(0.0, 0.08, 0.29),
        Err(MuscleError::Infeasible { .. })
    ));
    // … with implicit dynamics and damping, the damper carries the difference: β ṽ = f̃_T / cos α − f_PE.
    let mut damped = default_class();
    damped.tendon_compliance_dynamics_mode = "implicit".into();
    damped.fiber_damping = 0.2;
    let damped = muscle(DEFAULT_ARCHITECTURE, damped);
    let velocity = damped.fiber_velocity(0.0, 0.08, 0.29).unwrap();
    let curves = damped.curves();
    let along_tendon = (0.08f64.powi(2) - damped.fiber_width().powi(2)).sqrt();
    let tendon_force = curves.calc_tendon_force_multiplier((0.29 - along_tendon) / 0.2);
    let expected =
        (tendon_force * 0.08 / along_tendon - curves.calc_passive_force_multiplier(0.8)) / 0.2;
    assert!(
        (velocity / (10.0 * 0.1) - expected).abs() < 1e-12,
        "{velocity} vs {expected}"
    );
}

#[test]
fn without_damping_implicit_and_explicit_velocities_agree() {
    let mut implicit = default_class();
    implicit.tendon_compliance_dynamics_mode = "implicit".into();
    let implicit = muscle(DEFAULT_ARCHITECTURE, implicit);
    let explicit = muscle(DEFAULT_ARCHITECTURE, default_class());
    for (activation, mt_length) in [(0.2, 0.27), (0.9, 0.3), (1.0, 0.33)] {
        let at_rest = explicit
            .equilibrium(activation, mt_length)
            .unwrap()
            .fiber_length;
        for fiber_length in [0.998 * at_rest, 1.001 * at_rest] {
            let velocity = explicit
                .fiber_velocity(activation, fiber_length, mt_length)
                .unwrap();
            assert!(velocity != 0.0 && velocity.abs() < 10.0 * 0.1);
            assert_eq!(
                implicit
                    .fiber_velocity(activation, fiber_length, mt_length)
                    .unwrap(),
                velocity
            );
        }
    }
}
