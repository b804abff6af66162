//! A muscle's rest curve: once its rest fiber length L_rest is known (every coordinate 0,
//! minimum activation; `subject.json`'s reference), the (L_opt, L_ts) that reproduce it form a
//! curve, and the muscle keeps one free parameter. The curve coordinate s (natural log, 0 at the
//! origin's L_opt) runs along two branches:
//! - s ≤ s*: L_opt = L_opt,0·eˢ, and L_ts is the tendon slack length whose rest equilibrium has
//!   fiber length L_rest. The rest fiber length shortens as L_ts grows, so one L_ts does it;
//!   it is found by false position on a bracket grown from a hint.
//! - s > s*: L_opt = L_opt* and L_ts = L_ts*·e^(s − s*). L_opt* makes L_rest the muscle's
//!   minimum fiber length: a muscle slack at rest has its fiber held there (as OpenSim clamps
//!   it), and any longer tendon keeps it so. L_ts* is the shortest such tendon, where the two
//!   branches meet.
//!
//! The minimum fiber length is proportional to L_opt at fixed α_opt (both the active
//! force–length floor and the pennation limit are), so L_opt* = L_rest / (L_min/L_opt).

use super::error::FunctionalError;
use super::knee_moment::{EstimatedMuscles, KneeMomentModel};
use super::parameters::MuscleParameters;
use crate::mechanics::muscle::EquilibriumStatus;
use crate::solvers::false_position;

/// Relative bracket width at which L_ts counts as found.
const SLACK_TOLERANCE: f64 = 1e-13;
/// Growth factor of the bracket search around the hint.
const BRACKET_GROWTH: f64 = 1.05;
/// Points within this of s* take the clamped branch: there the unclamped branch's L_ts has a
/// flat root (every L_ts ≥ L_ts* gives the rest length) that no search resolves.
const CORNER: f64 = 1e-9;

/// The rest curve of estimated muscle `e`.
#[derive(Debug, Clone)]
pub struct RestCurve {
    pub e: usize,
    /// L_rest, m.
    pub reference: f64,
    /// The parameters at s = 0 (their L_ts is only a hint).
    origin: MuscleParameters,
    /// s* and L_ts* where the clamped branch begins; `None` when the class does not clamp.
    clamp: Option<(f64, f64)>,
}

impl RestCurve {
    /// The curve through `reference` (m) with origin `origin`; `workspace` is left with muscle
    /// `e` at `origin`.
    pub fn new(model: &KneeMomentModel, workspace: &mut EstimatedMuscles, e: usize, reference: f64, origin: &MuscleParameters) -> Result<RestCurve, FunctionalError> {
        if !(reference > 0.0 && reference.is_finite()) {
            return Err(FunctionalError::Parameters { muscle: origin.name.clone(), problem: format!("reference rest fiber length {reference} m; expected a positive length") });
        }
        let mut curve = RestCurve { e, reference, origin: origin.clone(), clamp: None };
        workspace.set(model, e, origin)?;
        let Some(minimum_ratio) = minimum_fiber_ratio(model, workspace, e) else { return Ok(curve) };
        let clamp_optimal = reference / minimum_ratio;
        let s_clamp = (clamp_optimal / origin.optimal_fiber_length).ln();
        let mut at_clamp = origin.clone();
        at_clamp.optimal_fiber_length = clamp_optimal;
        let slack = curve.shortest_clamping_slack(model, workspace, at_clamp);
        workspace.set(model, e, origin)?;
        curve.clamp = slack.map(|slack| (s_clamp, slack));
        Ok(curve)
    }

    pub fn origin(&self) -> &MuscleParameters {
        &self.origin
    }

    /// (s*, L_ts* in m) where the clamped branch starts, if the class clamps.
    pub fn clamp(&self) -> Option<(f64, f64)> {
        self.clamp
    }

    /// The s of the curve point nearest `parameters` in L_opt; where that is the clamped branch
    /// (L_opt ≥ L_opt*), its point nearest in L_ts — the corner s* for a tendon no longer than
    /// L_ts*.
    pub fn coordinate_of(&self, parameters: &MuscleParameters) -> f64 {
        let s = (parameters.optimal_fiber_length / self.origin.optimal_fiber_length).ln();
        match self.clamp {
            Some((s_clamp, slack)) if s >= s_clamp - CORNER => s_clamp + (parameters.tendon_slack_length / slack).ln().max(0.0),
            _ => s,
        }
    }

    /// (L_opt, L_ts) at s, starting the L_ts search at `slack_hint` (m); `None` where no L_ts
    /// gives the rest length (or an equilibrium fails). Leaves muscle `e` of `workspace` at the
    /// returned parameters.
    pub fn at(&self, model: &KneeMomentModel, workspace: &mut EstimatedMuscles, s: f64, slack_hint: f64) -> Option<MuscleParameters> {
        let mut parameters = self.origin.clone();
        if let Some((s_clamp, slack)) = self.clamp.filter(|(s_clamp, _)| s >= *s_clamp - CORNER) {
            parameters.optimal_fiber_length *= s_clamp.exp();
            parameters.tendon_slack_length = slack * (s - s_clamp).exp();
        } else {
            parameters.optimal_fiber_length *= s.exp();
            parameters.tendon_slack_length = self.slack_for_rest(model, workspace, &mut parameters, slack_hint)?;
        }
        workspace.set(model, self.e, &parameters).ok()?;
        Some(parameters)
    }

    /// The knee-moment contribution F_t·r (N·m) per trial at s into `out`, the L_ts search
    /// started at `slack_hint` (updated to the L_ts found); returns the curve point, `None`
    /// where it or a trial's equilibrium does not exist.
    pub fn contributions(&self, model: &KneeMomentModel, workspace: &mut EstimatedMuscles, s: f64, slack_hint: &mut f64, out: &mut [f64]) -> Option<MuscleParameters> {
        let parameters = self.at(model, workspace, s, *slack_hint)?;
        *slack_hint = parameters.tendon_slack_length;
        let k = model.estimated_knee_index(self.e);
        for (t, value) in out.iter_mut().enumerate() {
            *value = model.contribution(k, workspace.muscle(self.e), t).ok()?;
        }
        Some(parameters)
    }

    /// The L_ts whose rest fiber length is the reference at `parameters`' L_opt (its L_ts is
    /// overwritten by the search).
    fn slack_for_rest(&self, model: &KneeMomentModel, workspace: &mut EstimatedMuscles, parameters: &mut MuscleParameters, hint: f64) -> Option<f64> {
        let mut excess = |slack: f64| -> f64 {
            parameters.tendon_slack_length = slack;
            match workspace.set(model, self.e, parameters).and_then(|_| model.rest_state(self.e, workspace)) {
                Ok(state) => state.fiber_length - self.reference,
                Err(_) => f64::NAN,
            }
        };
        // The rest fiber is longer than the reference below the root, shorter above it.
        let [shortest, longest] = self.slack_range(model);
        let mut near = hint.clamp(shortest, longest);
        let mut f_near = excess(near);
        if !f_near.is_finite() {
            return None;
        }
        let rising = f_near > 0.0;
        loop {
            let far = if rising { (near * BRACKET_GROWTH).min(longest) } else { (near / BRACKET_GROWTH).max(shortest) };
            let f_far = excess(far);
            if !f_far.is_finite() {
                return None;
            }
            if (f_far > 0.0) != rising || f_far == 0.0 {
                let (ends, values) = if rising { ([near, far], [f_near, f_far]) } else { ([far, near], [f_far, f_near]) };
                return false_position(&mut excess, ends, values, SLACK_TOLERANCE * longest, 200);
            }
            if far == near {
                return None;
            }
            (near, f_near) = (far, f_far);
        }
    }

    /// The L_ts searched, m: 10⁻³ of the rest path length up to all of it.
    fn slack_range(&self, model: &KneeMomentModel) -> [f64; 2] {
        let mt_length = model.estimated_knee_muscle(self.e).rest_mt_length;
        [1e-3 * mt_length, mt_length]
    }

    /// At L_opt* the rest fiber reaches the reference (its minimum length) for every L_ts above
    /// L_ts*: bisection for the shortest such L_ts.
    fn shortest_clamping_slack(&self, model: &KneeMomentModel, workspace: &mut EstimatedMuscles, mut at_clamp: MuscleParameters) -> Option<f64> {
        let mut clamped = |slack: f64| -> Option<bool> {
            at_clamp.tendon_slack_length = slack;
            workspace.set(model, self.e, &at_clamp).ok()?;
            let state = model.rest_state(self.e, workspace).ok()?;
            Some(state.status == EquilibriumStatus::ClampedAtMinimumFiberLength || state.fiber_length <= self.reference)
        };
        let [mut lo, mut hi] = self.slack_range(model);
        let tolerance = SLACK_TOLERANCE * hi;
        if clamped(lo)? || !clamped(hi)? {
            return None;
        }
        while hi - lo > tolerance {
            let mid = 0.5 * (lo + hi);
            if clamped(mid)? {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        Some(hi)
    }
}

/// L_min/L_opt of muscle `e` as the workspace has it: the fiber length its equilibrium holds
/// when the path is too short for any balance; `None` for classes that do not clamp.
fn minimum_fiber_ratio(model: &KneeMomentModel, workspace: &EstimatedMuscles, e: usize) -> Option<f64> {
    let muscle = workspace.muscle(e);
    let state = model.equilibrium(muscle, model.estimated_knee_muscle(e).minimum_activation, 1e-6).ok()?;
    (state.status == EquilibriumStatus::ClampedAtMinimumFiberLength).then(|| state.fiber_length / workspace.parameters()[e].optimal_fiber_length)
}
