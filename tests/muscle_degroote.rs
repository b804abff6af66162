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

use std::collections::{BTreeMap, HashMap};

use osim_tune::io::osim::OsimDocument;
use osim_tune::mechanics::muscle::{
    DeGrooteCurves, DeGrooteFregly2016Muscle, EquilibriumStatus, FiberEquilibrium, HillMuscle,
    MuscleError,
};
use osim_tune::model::{DeGrooteSpec, ModelSpec, MuscleModelSpec, MuscleSpec};
use osim_tune::validation::GoldenTable;
use proptest::prelude::*;

fn golden(file: &str) -> GoldenTable {
    GoldenTable::read(&common::fixture(&format!("golden/muscle/degroote/{file}"))).unwrap()
}

use common::golden_rows::{rows, Row};

/// The bench model's muscles, each with its specification, as read from the .osim file.
fn bench_muscles() -> HashMap<String, (MuscleSpec, DeGrooteSpec, DeGrooteFregly2016Muscle)> {
    let document = OsimDocument::read(&common::fixture("models/degroote_bench.osim")).unwrap();
    let spec = ModelSpec::read(&document).unwrap();
    spec.muscles()
        .map(|force| {
            let muscle = force.muscle.clone().unwrap();
            let MuscleModelSpec::DeGrooteFregly2016(class) = muscle.model.clone() else {
                panic!("{}", force.name)
            };
            let built = DeGrooteFregly2016Muscle::new(&force.name, &muscle, &class).unwrap();
            assert!(matches!(
                HillMuscle::from_force(force),
                Ok(HillMuscle::DeGroote(_))
            ));
            (force.name.clone(), (muscle, class, built))
        })
        .collect()
}

fn within(ours: f64, theirs: f64, bound: f64, what: &str) -> f64 {
    let error = (ours - theirs).abs();
    assert!(
        error <= bound,
        "{what}: ours {ours}, OpenSim {theirs}, |Δ| = {error:e} > {bound:e}"
    );
    error
}

#[test]
fn the_bench_model_reads_as_opensim_wrote_it() {
    let muscles = bench_muscles();
    let parameters = golden("parameters.csv");
    assert_eq!(muscles.len(), parameters.rows.len());
    for row in rows(&parameters) {
        let (spec, class, _) = &muscles[row.text("muscle")];
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

/// The value and, where OpenSim has one, the derivative of curve function `function`.
fn evaluate(curves: &DeGrooteCurves, function: &str, x: f64) -> (f64, Option<f64>) {
    match function {
        "calcActiveForceLengthMultiplier" => (
            curves.calc_active_force_length_multiplier(x),
            Some(curves.calc_active_force_length_multiplier_derivative(x)),
        ),
        "calcPassiveForceMultiplier" => (
            curves.calc_passive_force_multiplier(x),
            Some(curves.calc_passive_force_multiplier_derivative(x)),
        ),
        "calcPassiveForceMultiplierIntegral" => {
            (curves.calc_passive_force_multiplier_integral(x), None)
        }
        "calcTendonForceMultiplier" => (
            curves.calc_tendon_force_multiplier(x),
            Some(curves.calc_tendon_force_multiplier_derivative(x)),
        ),
        "calcTendonForceMultiplierIntegral" => {
            (curves.calc_tendon_force_multiplier_integral(x), None)
        }
        "calcTendonForceLengthInverseCurve" => {
            (curves.calc_tendon_force_length_inverse_curve(x), None)
        }
        "calcForceVelocityMultiplier" => (DeGrooteCurves::calc_force_velocity_multiplier(x), None),
        "calcForceVelocityInverseCurve" => {
            (DeGrooteCurves::calc_force_velocity_inverse_curve(x), None)
        }
        other => panic!("unknown curve function {other}"),
    }
}

#[test]
fn curves_agree_with_opensim() {
    let sets: HashMap<String, DeGrooteCurves> = rows(&golden("curve_sets.csv"))
        .map(|row| {
            let curves = DeGrooteCurves::new(
                row.number("active_force_width_scale"),
                row.number("passive_fiber_strain_at_one_norm_force"),
                row.number("tendon_strain_at_one_norm_force"),
                false,
            );
            (row.text("set_id").to_string(), curves)
        })
        .collect();
    let table = golden("curves.csv");
    let mut worst = 0.0f64;
    for row in rows(&table) {
        let (function, x) = (row.text("function"), row.number("x"));
        let (value, derivative) = evaluate(&sets[row.text("set_id")], function, x);
        let what = format!("{function} set {} at {x}", row.text("set_id"));
        let expected = row.number("value");
        worst = worst.max(within(
            value,
            expected,
            1e-12 * expected.abs().max(1.0),
            &what,
        ));
        match derivative {
            Some(derivative) => {
                let expected = row.number("derivative");
                worst = worst.max(within(
                    derivative,
                    expected,
                    1e-12 * expected.abs().max(1.0),
                    &format!("d/dx {what}"),
                ));
            }
            None => assert!(
                row.number("derivative").is_nan(),
                "{what}: OpenSim exposes a derivative"
            ),
        }
    }
    assert_eq!(table.rows.len(), 772);
    println!("curves: worst |Δ| {worst:e}");
}

/// F_max (a f_L |f_V(ṽ) − f_V(0)| + β |ṽ|) (N): the fiber force OpenSim's explicit getters
/// attribute to the velocity its bisection leaves.
fn opensim_imbalance(row: &Row, spec: &MuscleSpec, class: &DeGrooteSpec) -> f64 {
    let f_max = spec.max_isometric_force;
    let at_rest = f_max
        * (row.number("activation")
            * row.number("active_force_length_multiplier")
            * DeGrooteCurves::calc_force_velocity_multiplier(0.0));
    (row.number("active_fiber_force") - at_rest).abs()
        + f_max * class.fiber_damping * row.number("normalized_fiber_velocity").abs()
}

/// Worst |Δ| per quantity over the rows compared.
#[derive(Debug, Default)]
struct Worst(BTreeMap<&'static str, f64>);

impl Worst {
    fn check(&mut self, what: &'static str, ours: f64, row: &Row, bound: f64) {
        let context = format!(
            "{} {} a={} {what}",
            row.text("muscle"),
            row.text("pose_id"),
            row.text("activation")
        );
        let error = within(ours, row.number(what), bound, &context);
        let entry = self.0.entry(what).or_default();
        *entry = entry.max(error);
    }
}

fn compare_equilibrium(ours: &FiberEquilibrium, row: &Row, imbalance: f64, worst: &mut Worst) {
    let lengths = [
        ("fiber_length", ours.fiber_length),
        ("fiber_length_along_tendon", ours.fiber_length_along_tendon),
        ("tendon_length", ours.tendon_length),
        ("normalized_fiber_length", ours.normalized_fiber_length),
        ("tendon_strain", ours.tendon_strain),
        ("pennation_angle", ours.pennation_angle),
        ("cos_pennation_angle", ours.cos_pennation_angle),
        (
            "active_force_length_multiplier",
            ours.active_force_length_multiplier,
        ),
        ("passive_force_multiplier", ours.passive_force_multiplier),
    ];
    for (what, value) in lengths {
        worst.check(what, value, row, 1e-8);
    }
    let tendon_force = row.number("tendon_force");
    let force_bound = 1e-6f64.max(1e-8 * tendon_force.abs());
    worst.check("tendon_force", ours.tendon_force, row, force_bound);
    for (what, value) in [
        ("active_fiber_force", ours.active_fiber_force),
        ("passive_fiber_force", ours.passive_fiber_force),
        ("fiber_force", ours.fiber_force),
        ("fiber_force_along_tendon", ours.fiber_force_along_tendon),
    ] {
        worst.check(what, value, row, force_bound + imbalance);
    }
    assert!(
        row.number("normalized_fiber_velocity").abs() <= 1e-6,
        "OpenSim left |ṽ| > 1e-6"
    );
    assert_eq!(ours.normalized_fiber_velocity, 0.0);
    assert_eq!(
        ours.force_velocity_multiplier,
        DeGrooteCurves::calc_force_velocity_multiplier(0.0)
    );
    assert_eq!(ours.status, EquilibriumStatus::Converged);
}

#[test]
fn equilibrium_agrees_with_opensim() {
    let muscles = bench_muscles();
    let table = golden("equilibrium.csv");
    let mut worst = Worst::default();
    let (mut compared, mut refused) = (0, 0);
    for row in rows(&table) {
        let (spec, class, muscle) = &muscles[row.text("muscle")];
        let (activation, mt_length) = (row.number("activation"), row.number("mt_length"));
        assert_eq!(row.number("activation_readback"), activation);
        let ours = muscle.equilibrium(activation, mt_length);
        let shorter_than_tendon = mt_length <= spec.tendon_slack_length;
        if row.text("status") == "ok" && !shorter_than_tendon {
            let ours = ours.unwrap_or_else(|e| panic!("{e}"));
            compare_equilibrium(
                &ours,
                &row,
                opensim_imbalance(&row, spec, class),
                &mut worst,
            );
            compared += 1;
        } else {
            // OpenSim threw, or (rigid tendon, L_mt < L_ts) reported a fiber pointing backwards.
            assert!(
                matches!(ours, Err(MuscleError::Infeasible { .. })),
                "{} {}: {ours:?}",
                row.text("muscle"),
                row.text("pose_id")
            );
            refused += 1;
        }
    }
    assert_eq!((compared, refused), (404, 76));
    println!("equilibrium worst |Δ|: {:#?}", worst.0);
}

#[test]
fn fiber_velocity_agrees_with_opensim() {
    let muscles = bench_muscles();
    let table = golden("fiber_velocity.csv");
    let mut worst = 0.0f64;
    for row in rows(&table) {
        let (_, _, muscle) = &muscles[row.text("muscle")];
        let (activation, fiber_length, mt_length) = (
            row.number("activation"),
            row.number("fiber_length"),
            row.number("mt_length"),
        );
        let ours = muscle
            .fiber_velocity(activation, fiber_length, mt_length)
            .unwrap();
        let expected = row.number("fiber_velocity");
        let what = format!(
            "{} a={activation} L_mt={mt_length} f_T={}",
            row.text("muscle"),
            row.text("normalized_tendon_force")
        );
        worst = worst.max(
            within(ours, expected, 1e-9 * expected.abs().max(1.0), &what) / expected.abs().max(1.0),
        );
    }
    assert_eq!(table.rows.len(), 243);
    println!("fiber velocity: worst |Δ| / max(1, |v|) {worst:e}");
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
