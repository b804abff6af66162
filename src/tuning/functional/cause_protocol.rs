//! The protocol's deficiencies as single causes (METHOD.md §8): a constant offset of one
//! recorded angle — knee, hip or ankle, e.g. the dynamometer's axis misaligned with the knee's or
//! a goniometer's zero off —, the agonists of one direction, of every trial, or one agonist
//! alone, activated at a factor of their recorded level, and a constant offset of the measured
//! moments (the dynamometer's zero, an uncorrected limb weight near the protocol's angles). An
//! angle offset rebuilds the knee-moment model from the changed trials at each evaluation
//! (about 1 ms of geometry for 70 trials); an activation keeps its geometry.

use super::cause::{Candidate, Cause};
use super::error::FunctionalError;
use super::knee_moment::KneeMomentModel;
use super::parameters::MuscleParameters;
use super::trials::{Direction, DynamometryData, IsometricTrial};
use crate::model::ModelSpec;

/// Largest angle offset tried, degrees.
pub const OFFSET_LIMIT_DEG: f64 = 15.0;

/// Smallest activation factor tried (the largest keeps every activation ≤ 1).
const LOWEST_ACTIVATION_FACTOR: f64 = 0.5;

/// What a protocol candidate changes in the trials.
#[derive(Debug, Clone)]
enum Protocol {
    /// Added to the knee (0), hip (1) or ankle (2) angle.
    Offset(usize),
    /// The agonists' activation of one direction's trials (`None`: of every trial).
    Activation(Option<Direction>),
    /// One agonist's activation, in every trial that records it.
    MuscleActivation(String),
}

/// A protocol deficiency as a one-variable model of the moment residuals: x is the offset in
/// degrees, or the logarithm of the activation factor.
pub(super) struct ProtocolCandidate<'a> {
    spec: &'a ModelSpec,
    data: &'a DynamometryData,
    model: &'a KneeMomentModel,
    initial: Vec<MuscleParameters>,
    measured: &'a [f64],
    protocol: Protocol,
}

/// The protocol candidates of `data`: the three angle offsets, the activation of each direction
/// with trials, of every trial when both directions have some, and of each agonist (in the
/// order the trials first record them).
pub(super) fn protocol_candidates<'a>(
    spec: &'a ModelSpec,
    model: &'a KneeMomentModel,
    data: &'a DynamometryData,
    initial: &[MuscleParameters],
    measured: &'a [f64],
) -> Vec<ProtocolCandidate<'a>> {
    let directions: Vec<Direction> = Direction::BOTH.into_iter().filter(|d| data.trials.iter().any(|t| t.direction == *d)).collect();
    let every_trial = (directions.len() > 1).then_some(None);
    let activations = directions.into_iter().map(Some).chain(every_trial).map(Protocol::Activation);
    let mut agonists: Vec<&String> = Vec::new();
    for (muscle, _) in data.trials.iter().flat_map(|t| &t.activations) {
        if !agonists.contains(&muscle) {
            agonists.push(muscle);
        }
    }
    let muscle_activations = agonists.into_iter().map(|m| Protocol::MuscleActivation(m.clone()));
    let protocols = (0..3).map(Protocol::Offset).chain(activations).chain(muscle_activations);
    protocols.map(|protocol| ProtocolCandidate { spec, data, model, initial: initial.to_vec(), measured, protocol }).collect()
}

impl ProtocolCandidate<'_> {
    pub fn cause(&self) -> Cause {
        let columns = &self.data.columns;
        match &self.protocol {
            Protocol::Offset(c) => Cause::AngleOffset { coordinate: [&columns.knee_angle, &columns.hip_flexion, &columns.ankle_angle][*c].clone() },
            Protocol::Activation(direction) => Cause::Activation { direction: *direction },
            Protocol::MuscleActivation(muscle) => Cause::MuscleActivation { muscle: muscle.clone() },
        }
    }

    /// The trials as the cause at x makes them.
    fn changed_trials(&self, x: f64) -> DynamometryData {
        let mut data = self.data.clone();
        for trial in &mut data.trials {
            if let Protocol::Offset(c) = self.protocol {
                *[&mut trial.knee_angle, &mut trial.hip_flexion, &mut trial.ankle_angle][c] += x.to_radians();
                continue;
            }
            for (muscle, a) in &mut trial.activations {
                if self.scales(trial.direction, muscle) {
                    *a *= x.exp();
                }
            }
        }
        data
    }

    /// Whether an activation candidate scales `muscle`'s activation in a trial of `direction`.
    fn scales(&self, direction: Direction, muscle: &str) -> bool {
        match &self.protocol {
            Protocol::Offset(_) => false,
            Protocol::Activation(scaled) => scaled.is_none_or(|d| d == direction),
            Protocol::MuscleActivation(scaled) => scaled == muscle,
        }
    }

    /// The highest recorded activation this candidate scales.
    fn highest_activation(&self) -> f64 {
        let scaled = self.data.trials.iter().flat_map(|t: &IsometricTrial| t.activations.iter().filter(|(m, _)| self.scales(t.direction, m)));
        scaled.map(|(_, a)| *a).fold(0.0, f64::max)
    }
}

/// A constant offset of the measured moments: x (N·m) is what every measurement carries beyond
/// the knee's moment, within ± the largest measured |moment|.
pub(super) struct MomentOffsetCandidate {
    /// M_mod − M_meas of the initial model, N·m.
    base: Vec<f64>,
    limit: f64,
}

impl MomentOffsetCandidate {
    /// The candidate from the initial model's `moments` and the `measured` ones (N·m).
    pub fn new(moments: &[f64], measured: &[f64]) -> MomentOffsetCandidate {
        let limit = measured.iter().fold(0.0f64, |m, y| m.max(y.abs()));
        MomentOffsetCandidate { base: moments.iter().zip(measured).map(|(m, y)| m - y).collect(), limit }
    }
}

impl Candidate for MomentOffsetCandidate {
    fn residuals(&mut self, x: &[f64], out: &mut [f64]) -> Result<(), FunctionalError> {
        for (r, base) in out.iter_mut().zip(&self.base) {
            *r = base + x[0];
        }
        Ok(())
    }

    fn bounds(&self) -> Vec<[f64; 2]> {
        vec![[-self.limit, self.limit]]
    }

    fn value(&self, x: &[f64]) -> f64 {
        x[0]
    }
}

impl Candidate for ProtocolCandidate<'_> {
    fn residuals(&mut self, x: &[f64], out: &mut [f64]) -> Result<(), FunctionalError> {
        let changed = self.changed_trials(x[0]);
        let model = match self.protocol {
            Protocol::Offset(_) => KneeMomentModel::with_method(self.spec, &changed, self.model.method)?,
            _ => self.model.with_activations(changed.trials)?,
        };
        for ((r, m), y) in out.iter_mut().zip(model.moments(&self.initial)?).zip(self.measured) {
            *r = m - y;
        }
        Ok(())
    }

    fn bounds(&self) -> Vec<[f64; 2]> {
        vec![match self.protocol {
            Protocol::Offset(_) => [-OFFSET_LIMIT_DEG, OFFSET_LIMIT_DEG],
            _ => [LOWEST_ACTIVATION_FACTOR.ln(), -self.highest_activation().max(f64::MIN_POSITIVE).ln()],
        }]
    }

    fn value(&self, x: &[f64]) -> f64 {
        match self.protocol {
            Protocol::Offset(_) => x[0],
            _ => x[0].exp(),
        }
    }
}
