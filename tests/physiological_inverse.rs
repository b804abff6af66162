//! The physiological inverse approach on subject01's walk (0.5–2 s, 95 frames, 92 muscles and six
//! residual actuators), checked from first principles and against static optimisation, which
//! `tests/static_optimization.rs` checks against OpenSim 4.6:
//! - with activation dynamics made immaterial (time constants × 1e-6) the sum-of-squares
//!   optimum over the motion is static optimisation's, frame by frame;
//! - with the model's time constants every frame still produces inverse dynamics, consecutive
//!   activations respect the activation-dynamics bounds, excitations lie in [0, 1], and the
//!   cost cannot fall below the unconstrained one;
//! - the min–max criterion's largest activation is no larger than any feasible solution's, the
//!   sum-of-squares one among them;
//! - with compliant tendons the Hill model's nonlinear forces meet inverse dynamics once the
//!   linearised re-solves settle.

mod common;

use osim_tune::analysis::{Contraction, Criterion, PhysiologicalInverseResult, PhysiologicalInverseSettings, MAX_LINEARISATIONS, SETTLED_VIOLATION};
use osim_tune::io::table::StorageTable;
use osim_tune::validation::Subject01Walk;

fn walk() -> Subject01Walk {
    Subject01Walk::load(&common::root()).unwrap()
}

#[test]
fn without_activation_dynamics_it_is_static_optimization() {
    let walk = walk();
    let golden = StorageTable::read(&common::fixture("golden/static_optimization/subject01_walk1_StaticOptimization_activation.sto")).unwrap();
    let so = walk.static_optimization(&golden, &common::fixture("golden/static_optimization")).unwrap();
    let pia = walk.physiological_inverse(&Subject01Walk::pia_settings(Criterion::SumOfSquares, 1e-6)).unwrap();
    assert_eq!(pia.activations.labels(), so.activations.labels());
    assert_eq!(pia.activations.n_rows(), so.activations.n_rows());
    let worst = pia.activations.values().iter().zip(so.activations.values()).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
    // One sparse interior point solve (gap 1e-9) against per-frame polished QPs: the controls
    // agree to the solver's accuracy along the objective's flattest directions (found 6.8e-6).
    assert!(worst <= 2e-5, "PIA without dynamics differs from static optimisation by {worst:e}");
}

#[test]
fn activation_dynamics_bind_consecutive_frames() {
    let walk = walk();
    let free = walk.physiological_inverse(&Subject01Walk::pia_settings(Criterion::SumOfSquares, 1e-6)).unwrap();
    let pia = walk.physiological_inverse(&Subject01Walk::pia_settings(Criterion::SumOfSquares, 1.0)).unwrap();
    assert!(pia.max_violation <= 1e-6, "generalized forces off inverse dynamics by {:e}", pia.max_violation);
    assert!(pia.sum_of_squares >= free.sum_of_squares * (1.0 - 1e-9), "{} < {}", pia.sum_of_squares, free.sum_of_squares);
    assert_within_activation_dynamics(&pia);
    let changed = pia.activations.values().iter().zip(free.activations.values()).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
    assert!(changed > 1e-2, "the walk's activations should need dynamics somewhere ({changed:e})");
}

/// Consecutive activations of all 92 muscles within gait2392's activation-dynamics bounds
/// (τ_a = 0.01 s, τ_d = 0.04 s), excitations in [0, 1].
fn assert_within_activation_dynamics(pia: &PhysiologicalInverseResult) {
    let (times, labels) = (pia.activations.times(), pia.activations.labels().to_vec());
    let rows: Vec<&[f64]> = pia.activations.rows().collect();
    let (activation, deactivation) = (0.01, 0.04);
    let muscles: Vec<usize> = (1..labels.len()).filter(|&j| pia.excitations.column_index(&labels[j]).is_some()).collect();
    assert_eq!(muscles.len(), 92);
    for &j in &muscles {
        for k in 1..rows.len() {
            let step = times[k] - times[k - 1];
            let (a, before) = (rows[k][j], rows[k - 1][j]);
            let rate = (a - before) / step;
            assert!(rate <= (1.0 - a) / activation + 1e-5 && rate >= -a / deactivation - 1e-5, "{} at {} s: ȧ {rate} with a {a}", labels[j], times[k]);
        }
    }
    assert!(pia.excitations.rows().all(|r| r[1..].iter().all(|u| (0.0..=1.0).contains(u))));
}

/// With compliant tendons the muscles pull with their Hill model's equilibrium forces, passive
/// force included: the linearised re-solves settle within their limit, the nonlinear forces meet
/// inverse dynamics at every frame, activation dynamics still binds, and the forces are not the
/// rigid tendon's a·F₁ (`tests/so_cli.rs` checks them against `analyze`'s equilibria).
#[test]
fn compliant_tendons_settle_on_the_hill_models_forces() {
    let walk = walk();
    let pia = walk.physiological_inverse(&PhysiologicalInverseSettings { contraction: Contraction::CompliantTendon { max_linearisations: MAX_LINEARISATIONS }, ..Subject01Walk::pia_settings(Criterion::SumOfSquares, 1.0) }).unwrap();
    assert!((1..MAX_LINEARISATIONS).contains(&pia.iterations), "{} re-solves", pia.iterations);
    assert!(pia.max_violation <= SETTLED_VIOLATION, "generalized forces off inverse dynamics by {:e}", pia.max_violation);
    assert_within_activation_dynamics(&pia);
    let rigid = walk.physiological_inverse(&Subject01Walk::pia_settings(Criterion::SumOfSquares, 1.0)).unwrap();
    let changed = pia.forces.values().iter().zip(rigid.forces.values()).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
    assert!(changed > 1.0, "compliant and rigid forces differ by {changed:e} N at most");
    // Fewer re-solves than it needs: reported as no solution, with how far it got.
    let short = PhysiologicalInverseSettings { contraction: Contraction::CompliantTendon { max_linearisations: pia.iterations - 1 }, ..Subject01Walk::pia_settings(Criterion::SumOfSquares, 1.0) };
    let message = walk.physiological_inverse(&short).unwrap_err().to_string();
    let expected = format!("the physiological inverse problem has no solution (the linearised Hill model has not settled after {} re-solves", pia.iterations - 1);
    assert!(message.contains(&expected), "{message}");
}

#[test]
fn min_max_lowers_the_largest_activation() {
    let walk = walk();
    let squares = walk.physiological_inverse(&Subject01Walk::pia_settings(Criterion::SumOfSquares, 1.0)).unwrap();
    let min_max = walk.physiological_inverse(&Subject01Walk::pia_settings(Criterion::MinMax, 1.0)).unwrap();
    assert!(min_max.max_violation <= 1e-6, "{:e}", min_max.max_violation);
    assert!(min_max.max_activation <= squares.max_activation + 1e-6, "{} > {}", min_max.max_activation, squares.max_activation);
}
