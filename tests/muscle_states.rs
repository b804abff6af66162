//! Muscle states away from equilibrium (`HillMuscle::state`, what OpenSim's MuscleAnalysis and
//! Actuation report), checked from first principles on every muscle of gait2392 (Thelen, Millard)
//! and Rajagopal2016 (Millard: rigid and compliant tendons, fiber damping): the fiber carries the
//! tendon's force, the pennation angle moves as the fiber does, and the path's power splits into
//! the tendon's and the fiber's. (Their values against OpenSim's: tests/run_cli.rs, AnalyzeTool.)

mod common;

use osim_tune::io::osim::OsimDocument;
use osim_tune::mechanics::muscle::{EquilibriumStatus, FixedWidthPennation, HillMuscle, MuscleState};
use osim_tune::model::{ModelSpec, MuscleSpec};

const MODELS: [&str; 3] = ["fixtures/golden/scale/subject01_simbody.osim", "models/gait2392_millard2012muscle.osim", "fixtures/models/Rajagopal2016.osim"];

/// Each muscle of each model with its architecture.
fn muscles() -> Vec<(HillMuscle, MuscleSpec)> {
    let mut muscles = Vec::new();
    for path in MODELS {
        let spec = ModelSpec::read(&OsimDocument::read(&common::root().join(path)).unwrap()).unwrap();
        for force in spec.muscles() {
            muscles.push((HillMuscle::from_force(force).unwrap(), force.muscle.clone().unwrap()));
        }
    }
    muscles
}

/// States around the static equilibrium: activations 0.05–1, path lengths from short to
/// stretched, the fiber 3 % either side of its equilibrium, the path shortening and lengthening.
fn states_of(muscle: &HillMuscle, spec: &MuscleSpec) -> Vec<MuscleState> {
    let mut states = Vec::new();
    for activation in [0.05, 0.5, 1.0] {
        for stretch in [0.7, 1.0, 1.2] {
            let length = spec.tendon_slack_length + stretch * spec.optimal_fiber_length * spec.pennation_angle_at_optimal.cos();
            let Ok(equilibrium) = muscle.equilibrium(activation, length) else { continue };
            for offset in [0.97, 1.0, 1.03] {
                for speed in [-0.3, 0.0, 0.4] {
                    states.push(muscle.state(activation, equilibrium.fiber_length * offset, length, speed).unwrap());
                }
            }
        }
    }
    states
}

#[test]
fn fiber_and_tendon_carry_one_force() {
    let mut checked = 0;
    for (muscle, spec) in muscles() {
        for state in states_of(&muscle, &spec) {
            let r = &state.report;
            if r.status == EquilibriumStatus::ClampedAtMinimumFiberLength {
                continue;
            }
            // Millard's damped velocity solve stops at 1e-10 F_max.
            let imbalance = r.fiber_force * r.cos_pennation_angle - r.tendon_force;
            assert!(imbalance.abs() <= 2e-10 * spec.max_isometric_force, "{muscle:?}: {imbalance} N");
            assert!((r.fiber_force - r.active_fiber_force - r.passive_fiber_force).abs() <= 1e-9 * spec.max_isometric_force);
            checked += 1;
        }
    }
    assert!(checked > 5000, "{checked}");
}

#[test]
fn the_path_power_splits_into_tendon_and_fiber_power() {
    for (muscle, spec) in muscles() {
        for state in states_of(&muscle, &spec) {
            let fiber = state.fiber_active_power + state.fiber_passive_power;
            // −F_t v_mt + F_t v_t + F_m v_m = v_m (F_m − F_t / cos α): the force balance's residual
            // (≤ 2e-10 F_max) times the fiber's speed.
            let tolerance = 1e-9 * spec.max_isometric_force * state.fiber_velocity.abs().max(1.0) / state.report.cos_pennation_angle;
            let sum = state.tendon_power + fiber;
            assert!((state.muscle_power() - sum).abs() <= tolerance, "{muscle:?}: {} W vs {sum} W", state.muscle_power());
            // The fiber's power is its force times its speed, F_m · dL_m/dt.
            assert!((fiber + state.report.fiber_force * state.fiber_velocity).abs() <= tolerance);
        }
    }
}

#[test]
fn the_pennation_angle_moves_with_the_fiber() {
    for (muscle, spec) in muscles() {
        let maximum = match &spec.model {
            osim_tune::model::MuscleModelSpec::Millard2012(m) => m.maximum_pennation_angle,
            osim_tune::model::MuscleModelSpec::Thelen2003(t) => t.maximum_pennation_angle,
            osim_tune::model::MuscleModelSpec::DeGrooteFregly2016(_) => continue,
        };
        let pennation = FixedWidthPennation::new(spec.optimal_fiber_length, spec.pennation_angle_at_optimal, maximum);
        for state in states_of(&muscle, &spec) {
            let (l, v) = (state.report.fiber_length, state.fiber_velocity);
            let h = 1e-6;
            let rate = (pennation.pennation_angle(l + h * v) - pennation.pennation_angle(l - h * v)) / (2.0 * h);
            assert!((state.pennation_angular_velocity - rate).abs() <= 1e-6 * rate.abs().max(1e-3), "{muscle:?}: {} vs {rate}", state.pennation_angular_velocity);
            // The tendon takes up what the fiber's projection does not: dL_t/dt = dL_mt/dt − d(L_m cos α)/dt
            // (a rigid tendon keeps its length).
            let projection = (l + h * v) * pennation.pennation_angle(l + h * v).cos() - (l - h * v) * pennation.pennation_angle(l - h * v).cos();
            let expected = if spec.ignore_tendon_compliance { 0.0 } else { state.lengthening_speed - projection / (2.0 * h) };
            assert!((state.tendon_velocity - expected).abs() <= 1e-6 * expected.abs().max(1e-3), "{muscle:?}: {} vs {expected}", state.tendon_velocity);
        }
    }
}

#[test]
fn a_fiber_held_at_its_minimum_length_rests_and_the_tendon_follows_the_path() {
    let mut held = 0;
    for (muscle, spec) in muscles().into_iter().filter(|(_, s)| !s.ignore_tendon_compliance) {
        let length = spec.tendon_slack_length + 0.2 * spec.optimal_fiber_length;
        let state = muscle.state(1.0, 1e-6, length, -0.2).unwrap();
        if state.report.status == EquilibriumStatus::ClampedAtMinimumFiberLength {
            assert_eq!((state.fiber_velocity, state.pennation_angular_velocity, state.report.active_fiber_force), (0.0, 0.0, 0.0));
            assert_eq!(state.tendon_velocity, -0.2);
            held += 1;
        }
    }
    assert!(held > 100, "{held}");
}

/// DeGroote–Fregly muscles (degroote_bench: pennated, damped, rigid, …; explicit tendon
/// dynamics — an implicit-mode muscle's state needs the tendon force's derivative and is an
/// error): from its normalized tendon force state the fiber develops that force without its
/// damping (OpenSim's explicit velocity leaves damping out), and the pennation and tendon rates
/// are the fixed-width ones.
#[test]
fn degroote_states_balance_the_tendon_force_without_damping() {
    let spec = ModelSpec::read(&OsimDocument::read(&common::fixture("models/degroote_bench.osim")).unwrap()).unwrap();
    let (mut checked, mut implicit) = (0, 0);
    for force in spec.muscles() {
        let (muscle, muscle_spec) = (HillMuscle::from_force(force).unwrap(), force.muscle.as_ref().unwrap());
        let length = muscle_spec.tendon_slack_length + muscle_spec.optimal_fiber_length * muscle_spec.pennation_angle_at_optimal.cos();
        for (tendon_force, speed) in [(0.2, -0.3), (0.5, 0.0), (0.8, 0.4)] {
            let state = match muscle.state(0.6, tendon_force, length, speed) {
                Ok(state) => state,
                Err(_) => {
                    implicit += 1;
                    continue;
                }
            };
            let r = &state.report;
            let damping = r.passive_fiber_force - r.passive_force_multiplier * muscle_spec.max_isometric_force;
            if !muscle_spec.ignore_tendon_compliance {
                assert!(((r.fiber_force - damping) * r.cos_pennation_angle - r.tendon_force).abs() <= 1e-9 * muscle_spec.max_isometric_force, "{}", force.name);
            }
            let (l, v, sin) = (r.fiber_length, state.fiber_velocity, r.pennation_angle.sin());
            assert!((state.pennation_angular_velocity + v / l * r.pennation_angle.tan()).abs() <= 1e-12 * (1.0 + state.pennation_angular_velocity.abs()));
            let tendon_velocity = speed - v * r.cos_pennation_angle + l * sin * state.pennation_angular_velocity;
            assert!((state.tendon_velocity - tendon_velocity).abs() <= 1e-12 * (1.0 + speed.abs()), "{}", force.name);
            checked += 1;
        }
    }
    assert!(checked >= 20 && implicit == 3, "{checked} {implicit}");
}
