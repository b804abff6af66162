//! The hot start of Phase II (thesis §6.2.3): among the feasible (L_opt, L_ts) grid points of
//! every estimated muscle, the combination whose knee moments come closest to the measured ones
//! (largest absolute difference over the trials). Each point's moment contribution per trial is
//! computed once; the combination is then found by coordinate descent (one muscle at a time,
//! the others held, until no muscle changes), which needs no product over the sets.

use serde::Serialize;

use super::error::FunctionalError;
use super::feasible_set::MuscleFeasibleSet;
use super::knee_moment::KneeMomentModel;
use super::parameters::MuscleParameters;

/// Sweeps of the coordinate descent allowed.
const MAX_SWEEPS: usize = 50;

/// The chosen combination.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct HotStart {
    pub parameters: Vec<MuscleParameters>,
    /// max_k |M_mod,k − M_meas,k| at the hot start, N·m.
    pub max_moment_error: f64,
    pub sweeps: usize,
}

/// The hot start from `sets` (one per estimated muscle, in order), starting the descent at each
/// muscle's feasible point nearest to `initial`.
pub fn hot_start(model: &KneeMomentModel, sets: &[MuscleFeasibleSet], initial: &[MuscleParameters], measured: &[f64]) -> Result<HotStart, FunctionalError> {
    let contributions = contributions(model, sets, initial)?;
    let mut choice: Vec<usize> = sets.iter().zip(initial).map(|(set, p)| nearest(set, p)).collect();
    let mut totals = model.fixed_moments().to_vec();
    for (e, table) in contributions.iter().enumerate() {
        add(&mut totals, &table[choice[e]], 1.0);
    }
    let mut sweeps = 0;
    while sweeps < MAX_SWEEPS {
        sweeps += 1;
        let mut changed = false;
        for (e, table) in contributions.iter().enumerate() {
            add(&mut totals, &table[choice[e]], -1.0);
            let error = |c: usize| totals.iter().zip(&table[c]).zip(measured).map(|((t, m), y)| (t + m - y).abs()).fold(0.0, f64::max);
            let errors: Vec<f64> = (0..table.len()).map(error).collect();
            let best = (0..table.len()).min_by(|&a, &b| errors[a].total_cmp(&errors[b])).unwrap_or(choice[e]);
            if errors[best] < errors[choice[e]] {
                choice[e] = best;
                changed = true;
            }
            add(&mut totals, &table[choice[e]], 1.0);
        }
        if !changed {
            break;
        }
    }
    let parameters = sets
        .iter()
        .zip(initial)
        .zip(&choice)
        .map(|((set, p), &c)| MuscleParameters { optimal_fiber_length: set.feasible[c].0, tendon_slack_length: set.feasible[c].1, ..p.clone() })
        .collect();
    let max_moment_error = totals.iter().zip(measured).map(|(t, y)| (t - y).abs()).fold(0.0, f64::max);
    Ok(HotStart { parameters, max_moment_error, sweeps })
}

/// `[muscle][feasible point][trial]`: F_t·r in N·m.
fn contributions(model: &KneeMomentModel, sets: &[MuscleFeasibleSet], initial: &[MuscleParameters]) -> Result<Vec<Vec<Vec<f64>>>, FunctionalError> {
    let mut workspace = model.estimated_muscles(initial)?;
    let trials = model.trials().len();
    let mut tables = Vec::with_capacity(sets.len());
    for (e, set) in sets.iter().enumerate() {
        let knee_index = model.estimated_knee_index(e);
        let mut table = Vec::with_capacity(set.feasible.len());
        for &(optimal, slack) in &set.feasible {
            workspace.set(model, e, &MuscleParameters { optimal_fiber_length: optimal, tendon_slack_length: slack, ..initial[e].clone() })?;
            table.push((0..trials).map(|t| model.contribution(knee_index, workspace.muscle(e), t)).collect::<Result<Vec<_>, _>>()?);
        }
        workspace.set(model, e, &initial[e])?;
        tables.push(table);
    }
    Ok(tables)
}

/// The feasible point with the smallest relative distance to `initial`'s (L_opt, L_ts).
fn nearest(set: &MuscleFeasibleSet, initial: &MuscleParameters) -> usize {
    let distance = |&(o, s): &(f64, f64)| (o / initial.optimal_fiber_length - 1.0).powi(2) + (s / initial.tendon_slack_length - 1.0).powi(2);
    (0..set.feasible.len()).min_by(|&a, &b| distance(&set.feasible[a]).total_cmp(&distance(&set.feasible[b]))).unwrap_or(0)
}

fn add(totals: &mut [f64], values: &[f64], sign: f64) {
    for (total, value) in totals.iter_mut().zip(values) {
        *total += sign * value;
    }
}
