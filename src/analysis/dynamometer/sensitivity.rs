//! How much M3D moves when the model's uncertain parameters do (thesis table 5.1): the knee's
//! axis turned about and moved along the shank's X (anterior) and Y (proximal) axes with the
//! reaction kept (eq. 5.5 at the perturbed axis), and each body's mass and mass center (along
//! its X and Y) in the knee's subtree and of the crank, with the trial rerun. Each parameter
//! is perturbed both ways; per frame the larger change counts.

use super::frame::{Axis, DynamometerFrame, DynamometerModel};
use crate::mechanics::{rotation_about, Body, Multibody, Vec3};

/// The perturbation sizes; [`Perturbations::THESIS`] are table 5.1's.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Perturbations {
    /// The knee axis' turn, rad.
    pub axis_angle: f64,
    /// The knee axis' shift, m.
    pub axis_offset: f64,
    /// kg.
    pub mass: f64,
    /// The mass centers' shift, m.
    pub mass_center: f64,
}

impl Perturbations {
    /// 10°, 2 cm, 0.25 kg, 2 cm.
    pub const THESIS: Perturbations = Perturbations { axis_angle: 10.0 * std::f64::consts::PI / 180.0, axis_offset: 0.02, mass: 0.25, mass_center: 0.02 };
}

/// One parameter's effect on M3D over the trial.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct SensitivityRow {
    pub parameter: String,
    /// The perturbation, with its unit.
    pub size: String,
    /// The largest |ΔM3D| over the frames, N·m.
    pub max_change: f64,
    /// Its root mean square over the frames, N·m.
    pub rms_change: f64,
}

/// The rows for `frames` (the trial on `multibody`); `rerun` runs the trial on a perturbed copy.
pub fn sensitivity(multibody: &Multibody, model: &DynamometerModel, frames: &[DynamometerFrame], sizes: &Perturbations, rerun: impl Fn(&Multibody) -> Vec<DynamometerFrame>) -> Vec<SensitivityRow> {
    let shank = &multibody.bodies[model.shank].name;
    let mut rows = Vec::new();
    for (k, direction) in ["X", "Y"].iter().enumerate() {
        let turned = |f: &DynamometerFrame, sign: f64| {
            let about = f.shank_rotation.column(k).into_owned();
            Axis { point: f.knee_axis.point, direction: rotation_about(&about, sign * sizes.axis_angle) * f.knee_axis.direction }
        };
        let changes = axis_changes(frames, turned);
        rows.push(row(format!("knee axis turned about {shank} {direction}"), format!("{:.3}°", sizes.axis_angle.to_degrees()), &changes));
        let moved = |f: &DynamometerFrame, sign: f64| Axis { point: f.knee_axis.point + sign * sizes.axis_offset * f.shank_rotation.column(k), direction: f.knee_axis.direction };
        rows.push(row(format!("knee axis moved along {shank} {direction}"), format!("{:.1} mm", sizes.axis_offset * 1e3), &axis_changes(frames, moved)));
    }
    let bodies = (0..multibody.bodies.len()).filter(|&b| b == model.crank || (multibody.is_moved_by(b, model.knee_joint) && multibody.bodies[b].mass > 0.0));
    for b in bodies {
        let name = &multibody.bodies[b].name;
        let rerun_with = |change: &dyn Fn(&mut Body, f64)| {
            body_changes(frames, [1.0, -1.0].iter().map(|&sign| {
                let mut perturbed = multibody.clone();
                change(&mut perturbed.bodies[b], sign);
                rerun(&perturbed)
            }))
        };
        let mass = sizes.mass;
        let changes = rerun_with(&|body, sign| body.mass = (body.mass + sign * mass).max(0.0));
        rows.push(row(format!("{name} mass"), format!("{mass:.3} kg"), &changes));
        for (k, direction) in ["X", "Y"].iter().enumerate() {
            let shift = sizes.mass_center * Vec3::ith(k, 1.0);
            let changes = rerun_with(&|body, sign| body.mass_center += sign * shift);
            rows.push(row(format!("{name} mass center along {direction}"), format!("{:.1} mm", sizes.mass_center * 1e3), &changes));
        }
    }
    rows
}

/// Per frame, the larger |ΔM3D| of the axis perturbed both ways by `perturbed`.
fn axis_changes(frames: &[DynamometerFrame], perturbed: impl Fn(&DynamometerFrame, f64) -> Axis) -> Vec<f64> {
    frames
        .iter()
        .map(|f| {
            let base = f.knee_moment_about(&f.knee_axis);
            [1.0, -1.0].iter().map(|&sign| (f.knee_moment_about(&perturbed(f, sign)) - base).abs()).fold(0.0, f64::max)
        })
        .collect()
}

/// Per frame, the larger |ΔM3D| of the reruns.
fn body_changes(frames: &[DynamometerFrame], reruns: impl Iterator<Item = Vec<DynamometerFrame>>) -> Vec<f64> {
    let mut changes = vec![0.0f64; frames.len()];
    for rerun in reruns {
        for ((change, base), perturbed) in changes.iter_mut().zip(frames).zip(&rerun) {
            *change = change.max((perturbed.knee_moment - base.knee_moment).abs());
        }
    }
    changes
}

fn row(parameter: String, size: String, changes: &[f64]) -> SensitivityRow {
    let rms = (changes.iter().map(|c| c * c).sum::<f64>() / changes.len().max(1) as f64).sqrt();
    SensitivityRow { parameter, size, max_change: changes.iter().copied().fold(0.0, f64::max), rms_change: rms }
}
