//! Millard2012EquilibriumMuscle against OpenSim 4.6 (`fixtures/golden/muscle/`, a slice of the
//! reference goldens: every 4th curve sample, and the equilibrium rows of the first, middle and
//! last angle of each knee sweep at activations 0.05, 0.5, 0.8 and 1).

mod common;

use osim_tune::io::osim::OsimDocument;
use osim_tune::mechanics::muscle::{HillMuscle, Millard2012Muscle};
use osim_tune::model::ModelSpec;
use osim_tune::validation::{compare_equilibrium, compare_millard_curves, EquilibriumSolution};

fn model(path: &str) -> ModelSpec {
    ModelSpec::read(&OsimDocument::read(&common::root().join(path)).unwrap()).unwrap()
}

fn first_millard(spec: &ModelSpec) -> Millard2012Muscle {
    let force = spec.forces.iter().find(|f| f.muscle.is_some()).unwrap();
    match HillMuscle::from_force(force).unwrap() {
        HillMuscle::Millard(m) => *m,
        other => panic!("{other:?}"),
    }
}

#[test]
fn curves_equal_opensims() {
    for (stem, path) in [
        (
            "gait2392_millard2012muscle",
            "models/gait2392_millard2012muscle.osim",
        ),
        ("Rajagopal2016", "fixtures/models/Rajagopal2016.osim"),
    ] {
        let muscle = first_millard(&model(path));
        let c = compare_millard_curves(&muscle, &common::fixture(&format!("golden/muscle/{stem}")))
            .unwrap();
        assert_eq!(c.value.count, 505);
        assert!(
            c.value.error <= 1e-12,
            "{stem}: value off by {:e} at {}",
            c.value.error,
            c.value.at
        );
        assert!(
            c.first_derivative.error <= 1e-10,
            "{stem}: d1 off by {:e} at {}",
            c.first_derivative.error,
            c.first_derivative.at
        );
        assert!(
            c.second_derivative.error <= 1e-9,
            "{stem}: d2 off by {:e} at {}",
            c.second_derivative.error,
            c.second_derivative.at
        );
    }
}

/// Every golden row: OpenSim's iteration reproduced within 1e-8 m and max(1e-6 N, 1e-8 F_t);
/// the exact static balance within those plus the row's own OpenSim imbalance (OpenSim stops
/// at 1e-8 F_max), as `validation::compare_equilibrium` documents.
#[test]
fn equilibrium_equals_opensims() {
    for (stem, path) in [
        (
            "gait2392_millard2012muscle",
            "models/gait2392_millard2012muscle.osim",
        ),
        ("Rajagopal2016", "fixtures/models/Rajagopal2016.osim"),
    ] {
        let spec = model(path);
        let folder = common::fixture(&format!("golden/muscle/{stem}"));
        for solution in [EquilibriumSolution::OpenSim, EquilibriumSolution::Static] {
            let c = compare_equilibrium(&spec, &folder, solution).unwrap();
            assert!(
                c.outside_tolerance.is_empty(),
                "{stem} {solution:?}: {:#?}",
                c.outside_tolerance
            );
        }
    }
}

mod properties {
    use super::*;
    use osim_tune::mechanics::muscle::{EquilibriumStatus, MuscleError};
    use proptest::prelude::*;

    /// The 13 right-knee muscles of gait2392 (Millard), built once.
    fn knee_muscles() -> Vec<Millard2012Muscle> {
        let spec = model("models/gait2392_millard2012muscle.osim");
        let knee = [
            "bifemlh_r",
            "bifemsh_r",
            "grac_r",
            "lat_gas_r",
            "med_gas_r",
            "rect_fem_r",
            "sar_r",
            "semimem_r",
            "semiten_r",
            "tfl_r",
            "vas_int_r",
            "vas_lat_r",
            "vas_med_r",
        ];
        knee.iter()
            .map(|name| {
                match HillMuscle::from_force(spec.forces.iter().find(|f| f.name == *name).unwrap())
                    .unwrap()
                {
                    HillMuscle::Millard(m) => *m,
                    other => panic!("{other:?}"),
                }
            })
            .collect()
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(256))]

        /// For a ∈ [0.01, 1] and a path that stretches the tendon (L_mt from L_ts + the slack
        /// fiber to L_ts + 1.7 L_opt), the static solution balances fiber and tendon to 1e-9 N
        /// and is the only sign change of the balance on [L_min, L_slack] (sampled at 400 points).
        #[test]
        fn static_equilibrium_balances_and_is_unique(index in 0usize..13, a in 0.01f64..=1.0, stretch in 0.3f64..1.7) {
            let muscles = knee_muscles();
            let m = &muscles[index];
            let mt_length = m.tendon_slack_length + stretch * m.optimal_fiber_length;
            let e = m.equilibrium(a, mt_length).unwrap();
            prop_assert!(e.fiber_length.is_finite() && e.tendon_force.is_finite());
            if e.status == EquilibriumStatus::Converged {
                let (balance, _) = m.force_balance(a, e.fiber_length, mt_length);
                prop_assert!(balance.abs() <= 1e-9, "{}: balance {balance:e} N", m.name);
                let slack = (m.pennation.parallelogram_height.powi(2) + (mt_length - m.tendon_slack_length).powi(2)).sqrt();
                let samples: Vec<f64> = (0..=400).map(|i| m.minimum_fiber_length + (slack - m.minimum_fiber_length) * i as f64 / 400.0).collect();
                let changes = samples.windows(2).filter(|w| (m.force_balance(a, w[0], mt_length).0 < 0.0) != (m.force_balance(a, w[1], mt_length).0 < 0.0)).count();
                prop_assert_eq!(changes, 1, "{}: the balance changes sign {} times", m.name, changes);
            } else {
                prop_assert_eq!(e.fiber_length, m.minimum_fiber_length);
                prop_assert_eq!(e.fiber_force, 0.0);
            }
        }
    }

    #[test]
    fn a_path_shorter_than_tendon_and_shortest_fiber_leaves_the_muscle_slack() {
        let muscles = knee_muscles();
        let m = &muscles[10];
        let e = m.equilibrium(1.0, m.tendon_slack_length).unwrap();
        assert_eq!(e.status, EquilibriumStatus::ClampedAtMinimumFiberLength);
        assert_eq!(
            (e.fiber_length, e.tendon_force, e.fiber_force),
            (m.minimum_fiber_length, 0.0, 0.0)
        );
    }

    #[test]
    fn bad_activations_and_lengths_are_refused() {
        let m = &knee_muscles()[0];
        for (a, l) in [
            (-0.1, 0.5),
            (1.5, 0.5),
            (f64::NAN, 0.5),
            (0.5, 0.0),
            (0.5, -1.0),
            (0.5, f64::NAN),
            (0.5, f64::INFINITY),
        ] {
            let refused = m.equilibrium(a, l);
            assert!(
                matches!(refused, Err(MuscleError::InvalidInput { .. })),
                "a {a}, L_mt {l}: {refused:?}"
            );
        }
    }
}

/// Curve parameters OpenSim refuses are errors naming the muscle and the property.
#[test]
fn curve_parameters_opensim_refuses_are_errors() {
    use osim_tune::mechanics::muscle::MuscleError;
    use osim_tune::model::MuscleModelSpec;
    let spec = model("models/gait2392_millard2012muscle.osim");
    let force = spec.forces.iter().find(|f| f.name == "vas_int_r").unwrap();
    let base = force.muscle.clone().unwrap();
    type Edit = fn(&mut osim_tune::model::MillardSpec);
    let edits: [(&str, Edit); 5] = [
        ("min_norm_active_fiber_length", |m| {
            m.active_force_length.transition_norm_fiber_length = 0.3
        }),
        ("shallow_ascending_slope", |m| {
            m.active_force_length.shallow_ascending_slope = 5.0
        }),
        ("max_eccentric_velocity_force_multiplier", |m| {
            m.force_velocity.max_eccentric_velocity_force_multiplier = 0.9
        }),
        ("strain_at_one_norm_force", |m| {
            m.fiber_force_length.strain_at_one_norm_force = -0.1
        }),
        ("norm_force_at_toe_end", |m| {
            m.tendon_force_length.stiffness_at_one_norm_force = Some(30.0);
            m.tendon_force_length.norm_force_at_toe_end = Some(1.2);
            m.tendon_force_length.curviness = Some(0.5);
        }),
    ];
    for (property, edit) in edits {
        let mut muscle = base.clone();
        let MuscleModelSpec::Millard2012(class) = &mut muscle.model else {
            panic!()
        };
        edit(class);
        match HillMuscle::new("vas_int_r", &muscle) {
            Err(MuscleError::InvalidParameter {
                muscle,
                property: found,
                ..
            }) => {
                assert_eq!(muscle, "vas_int_r");
                assert!(found.ends_with(property), "{found} for {property}");
            }
            other => panic!("{property}: {other:?}"),
        }
    }
}
