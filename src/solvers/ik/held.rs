//! Links held exactly (OpenSim's infinite constraint weight) by an augmented Lagrangian, for
//! inverse kinematics and assembly: each round minimises the frame's objective with each link
//! error's residual √w·(e + s), the shift s = λ/w² then moving by the error.

use super::coordinates::CoordinateMap;
use super::frame::{FrameModel, FrameObjective, LinkTerms};
use super::solver::IkWorkspace;
use crate::mechanics::Vec3;
use crate::solvers::least_squares::{LeastSquaresOptions, LeastSquaresStatus};

/// √weight (per m) of the links' augmented-Lagrangian residuals (and of a Kalman frame's
/// linearised link residuals): large against the markers' √(w/W) so that a few rounds close
/// them.
pub(super) const LINK_ROOT_WEIGHT: f64 = 1e3;
/// The largest link error (m; rad for a weld's orientation) a solution may keep: Simbody
/// assembles to far less than OpenSim's IK accuracy.
const LINK_TOLERANCE: f64 = 1e-10;
/// Augmented-Lagrangian rounds per frame before the link is reported open.
const MAX_LINK_ROUNDS: usize = 30;
/// A round that leaves the largest link error above this fraction of the last round's stiffens
/// the links' √weight by LINK_STIFFENING, up to MAX_LINK_ROOT_WEIGHT: a link whose error moves
/// only at second order with the coordinates (a planar leg's toe held out of plane by an oblique
/// ankle) needs a multiplier far larger than the first weight reaches in a few rounds.
const LINK_PROGRESS: f64 = 0.25;
const LINK_STIFFENING: f64 = 10.0;
const MAX_LINK_ROOT_WEIGHT: f64 = 1e7;

/// A minimum found: the least-squares iterations over all rounds, the last round's status and
/// its cost.
pub(super) struct HeldMinimum {
    pub iterations: usize,
    pub status: LeastSquaresStatus,
    pub cost: f64,
}

/// A link the augmented Lagrangian left open: its index in `Multibody::links`, its largest
/// error and the rounds run.
pub(super) struct OpenLink {
    pub link: usize,
    pub error: f64,
    pub rounds: usize,
}

/// Minimises `model`'s objective from the free values in `workspace.x` (markers `observed`,
/// scaled by `workspace.scales`) and sets `q` to the minimum. With `exact`, the links are held
/// by an augmented Lagrangian: each round solves with each link error's residual shifted by its
/// multiplier estimate, which then moves by the error (the weight growing when the errors shrink
/// too slowly), until every error is within LINK_TOLERANCE (MAX_LINK_ROUNDS at most); the
/// shifts left in `workspace` are scaled to the first weight for the next frame. Otherwise the
/// links are goals √w·e.
pub(super) fn minimize_holding_links(
    model: &FrameModel,
    map: &CoordinateMap,
    observed: &[Option<Vec3>],
    workspace: &mut IkWorkspace,
    convergence: &LeastSquaresOptions,
    exact: bool,
    q: &mut [f64],
) -> Result<HeldMinimum, OpenLink> {
    let multibody = model.multibody;
    let mut root_weight = if exact { LINK_ROOT_WEIGHT } else { map.root_weight };
    let (mut iterations, mut round, mut previous) = (0, 0, f64::INFINITY);
    loop {
        round += 1;
        let links = LinkTerms { root_weight, shifts: &workspace.link_shifts };
        let mut objective = FrameObjective { model, map, scratch: &mut workspace.frame, observed, scales: &workspace.scales, targets: &workspace.targets, links };
        let report = workspace.least_squares.minimize(&mut objective, &mut workspace.x, &map.bounds, convergence);
        iterations += report.iterations;
        map.pose(multibody, &workspace.x, q);
        if !exact {
            return Ok(HeldMinimum { iterations, status: report.status, cost: report.cost });
        }
        multibody.realize(q, &mut workspace.frame.kinematics);
        let errors = multibody.link_errors(&workspace.frame.kinematics);
        let owners = multibody.links.iter().enumerate().flat_map(|(k, link)| std::iter::repeat_n(k, link.rows()));
        let (error, link) = errors.iter().zip(owners).map(|(e, k)| (e.abs(), k)).fold((0.0, 0), |a, b| if b.0 > a.0 { b } else { a });
        let closed = error <= LINK_TOLERANCE;
        if !closed && round < MAX_LINK_ROUNDS {
            workspace.link_shifts.iter_mut().zip(errors).for_each(|(shift, error)| *shift += error);
        }
        // The multipliers λ = w²·shift stay; only the shifts' scale follows the weight w.
        let stiffen = |shifts: &mut [f64], factor: f64| shifts.iter_mut().for_each(|shift| *shift /= factor * factor);
        if closed || round == MAX_LINK_ROUNDS {
            stiffen(&mut workspace.link_shifts, LINK_ROOT_WEIGHT / root_weight);
            return if closed { Ok(HeldMinimum { iterations, status: report.status, cost: report.cost }) } else { Err(OpenLink { link, error, rounds: round }) };
        }
        if error > LINK_PROGRESS * previous && root_weight < MAX_LINK_ROOT_WEIGHT {
            root_weight *= LINK_STIFFENING;
            stiffen(&mut workspace.link_shifts, LINK_STIFFENING);
        }
        previous = error;
    }
}
