//! OpenSim's `InducedAccelerations` analysis (`InducedAccelerations.cpp`) on the AnalyzeTool's
//! states: what each force contributes to the accelerations of coordinates, bodies and the whole
//! model's mass center, with the external forces replaced by contacts ([`contacts`]).
//!
//! Each row is solved once per contributor, the links and contacts holding: `total` (every
//! actuator at its force, gravity, the speeds), each actuator alone at its force with the speeds
//! zeroed (a rigid tendon's fiber then at rest; with `compute_potentials_only` a muscle at 1 N
//! and no `total`), `gravity` alone at rest, and `velocity` (the speeds alone). Which rows of a
//! rolling contact hold is settled by `total`'s multipliers, contact by contact in order, and
//! kept for the other contributors, as OpenSim does. OpenSim's quirks are kept: every
//! coordinate's acceleration (translations too) is scaled to degrees with `in_degrees`, and the
//! reactions are the forces the multipliers generate (Gᵀλ, the negated forces on the bodies).

mod contacts;

use std::path::{Path, PathBuf};

use nalgebra::DVector;

use self::contacts::{Contact, RowsHeld, ROLLING_ROWS};
use super::reporters::AppliedAt;
use crate::io::table::{StorageTable, TableError};
use crate::mechanics::{AppliedForces, BodyLink, ForwardDynamicsError, Kinematics, MotionState, Multibody, MuscleGeometry, PathScratch, Vec3};
use crate::setup::InducedAccelerationsSetup;

/// Why the analysis cannot run.
#[derive(Debug, thiserror::Error)]
pub enum InducedAccelerationsError {
    #[error("{}:{line}: InducedAccelerations: {problem}", file.display())]
    Contact { file: PathBuf, line: usize, problem: String },
    #[error("{}: InducedAccelerations names {what} {name:?}, which the model does not have", file.display())]
    Unknown { file: PathBuf, what: &'static str, name: String },
    #[error("InducedAccelerations at {time} s, contributor {contributor}: {source}")]
    Dynamics { time: f64, contributor: String, source: ForwardDynamicsError },
    #[error(transparent)]
    Table(#[from] TableError),
}

/// The whole model's mass center, as OpenSim names it among the bodies.
const CENTER_OF_MASS: &str = "center_of_mass";

/// What a contributor applies.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Contributor {
    Total,
    Generator(usize),
    Gravity,
    Velocity,
}

/// The tables of `setup` at `at`'s rows on `geometry`'s model, whose BodySet is `bodies`
/// ([`Multibody::bodies`] indices); `file` is the setup, for messages.
pub fn induced_acceleration_tables(geometry: &MuscleGeometry, at: &AppliedAt, setup: &InducedAccelerationsSetup, bodies: &[usize], file: &Path) -> Result<InducedAccelerationTables, InducedAccelerationsError> {
    let multibody = &geometry.multibody;
    let coordinates = reported_coordinates(multibody, setup, file)?;
    let (bodies, center_of_mass) = reported_bodies(multibody, setup, bodies, file)?;
    let applied = at.external.map(|e| e.applied_bodies()).unwrap_or_default();
    let contacts = Contact::compile(&setup.constraints, multibody, &applied, file)?;
    let mut contributors: Vec<(String, Contributor)> = Vec::new();
    if !setup.compute_potentials_only {
        contributors.push(("total".into(), Contributor::Total));
    }
    contributors.extend(at.generators.iter().enumerate().map(|(g, generator)| (generator.name.clone(), Contributor::Generator(g))));
    contributors.extend([("gravity".into(), Contributor::Gravity), ("velocity".into(), Contributor::Velocity)]);
    let mut recorder = Recorder::new(multibody, coordinates, bodies, center_of_mass);
    let run = Run { geometry, at, setup, contacts: &contacts, contributors: &contributors };
    let mut contacted = multibody.clone();
    let mut scratch = PathScratch::default();
    for row in 0..at.states.motion.len() {
        run.row(row, &mut contacted, &mut scratch, &mut recorder)?;
    }
    let notes = contacts.iter().filter_map(|c| c.fixed_points_note(multibody)).collect();
    Ok(InducedAccelerationTables { tables: recorder.tables(&run)?, notes })
}

/// The analysis' tables and what to tell about them.
#[derive(Debug, Clone)]
pub struct InducedAccelerationTables {
    /// (file suffix, table): each coordinate's, each body's, the mass center's, the reactions'.
    pub tables: Vec<(String, StorageTable)>,
    /// Where we hold contacts as OpenSim does rather than as the setup may mean.
    pub notes: Vec<String>,
}

/// The coordinates reported: the listed ones, or every one when the first is `All` (any case).
fn reported_coordinates(multibody: &Multibody, setup: &InducedAccelerationsSetup, file: &Path) -> Result<Vec<usize>, InducedAccelerationsError> {
    if setup.coordinate_names.first().is_some_and(|n| n.eq_ignore_ascii_case("all")) {
        return Ok((0..multibody.coordinates.len()).collect());
    }
    let unknown = |name: &String| InducedAccelerationsError::Unknown { file: file.into(), what: "coordinate", name: name.clone() };
    setup.coordinate_names.iter().map(|name| multibody.coordinate_index(name).ok_or_else(|| unknown(name))).collect()
}

/// The bodies reported and whether the mass center is: every body of the BodySet when the first
/// is `All` (any case; the mass center then not), else the listed ones and `center_of_mass`.
fn reported_bodies(multibody: &Multibody, setup: &InducedAccelerationsSetup, bodies: &[usize], file: &Path) -> Result<(Vec<usize>, bool), InducedAccelerationsError> {
    if setup.body_names.first().is_some_and(|n| n.eq_ignore_ascii_case("all")) {
        return Ok((bodies.to_vec(), false));
    }
    let (mut recorded, mut center_of_mass) = (Vec::new(), false);
    for name in &setup.body_names {
        if name.eq_ignore_ascii_case(CENTER_OF_MASS) {
            center_of_mass = true;
        } else {
            let body = bodies.iter().copied().find(|&b| &multibody.bodies[b].name == name);
            recorded.push(body.ok_or_else(|| InducedAccelerationsError::Unknown { file: file.into(), what: "body", name: name.clone() })?);
        }
    }
    Ok((recorded, center_of_mass))
}

/// One analysis over the rows.
struct Run<'a> {
    geometry: &'a MuscleGeometry,
    at: &'a AppliedAt<'a>,
    setup: &'a InducedAccelerationsSetup,
    contacts: &'a [Contact],
    contributors: &'a [(String, Contributor)],
}

/// The contacts placed at one row: each's point (m, ground) and held rows, `None` while its
/// force is within the threshold.
type Placed = Vec<Option<(Vec3, RowsHeld)>>;

impl Run<'_> {
    /// Solves and records every contributor at `row` on `contacted` (a copy of the model whose
    /// links the contacts join, [`Run::solve`]).
    fn row(&self, row: usize, contacted: &mut Multibody, scratch: &mut PathScratch, recorder: &mut Recorder) -> Result<(), InducedAccelerationsError> {
        let multibody = &self.geometry.multibody;
        let (time, q, u) = (self.at.states.motion.times[row], self.at.states.motion.pose(row), &self.at.states.speeds[row]);
        let mut kinematics = multibody.kinematics();
        multibody.realize(q, &mut kinematics);
        let loads = self.at.external.map(|e| e.at(time, &kinematics)).unwrap_or_default();
        let mut placed: Placed = loads.iter().map(|load| (load.force.norm() > self.setup.force_threshold).then_some((load.point, [true; ROLLING_ROWS]))).collect();
        let forces = self.at.forces(row);
        recorder.start(time);
        for (name, contributor) in self.contributors {
            let failed = |source| InducedAccelerationsError::Dynamics { time, contributor: name.clone(), source };
            let (speeds, applied, gravity) = self.applied(row, *contributor, &forces, &kinematics, u, scratch);
            let mut solved = self.solve(contacted, &kinematics, &placed, q, &speeds, &applied, gravity).map_err(failed)?;
            if *contributor == Contributor::Total {
                for k in 0..self.contacts.len() {
                    let Some((_, held)) = placed[k] else { continue };
                    let kept = self.contacts[k].rows_kept(&held, solved.contact_multipliers(k));
                    if kept != held {
                        placed[k] = placed[k].map(|(point, _)| (point, kept));
                        solved = self.solve(contacted, &kinematics, &placed, q, &speeds, &applied, gravity).map_err(failed)?;
                    }
                }
            }
            recorder.record(self, &kinematics, &solved, q, &speeds);
        }
        Ok(())
    }

    /// What `contributor` applies at `row` (each generator's force `forces` at the state): the
    /// speeds, the forces and whether gravity pulls.
    fn applied(&self, row: usize, contributor: Contributor, forces: &[f64], kinematics: &Kinematics, u: &[f64], scratch: &mut PathScratch) -> (Vec<f64>, AppliedForces, bool) {
        let n = u.len();
        let mut applied = AppliedForces::new(n);
        let q = self.at.states.motion.pose(row);
        let mut apply = |g: usize, force: f64| self.at.generators[g].apply(self.geometry, kinematics, q, scratch, force, &mut applied);
        match contributor {
            Contributor::Total => {
                forces.iter().enumerate().for_each(|(g, &force)| apply(g, force));
                (u.to_vec(), applied, true)
            }
            Contributor::Generator(g) => {
                let generator = &self.at.generators[g];
                let force = match (generator.muscle_path(), self.setup.compute_potentials_only) {
                    (Some(_), true) => 1.0,
                    (Some(_), false) => self.at.muscle_state(row, g).map_or(f64::NAN, |state| generator.force_at_rest(state)),
                    (None, _) => forces[g],
                };
                apply(g, force);
                (vec![0.0; n], applied, false)
            }
            Contributor::Gravity => (vec![0.0; n], applied, true),
            Contributor::Velocity => (u.to_vec(), applied, false),
        }
    }

    /// The accelerations with the contacts `placed` holding (gravity on or off), solved on
    /// `contacted`, the model to which the contacts are added as links after its own.
    #[allow(clippy::too_many_arguments)]
    fn solve(&self, contacted: &mut Multibody, kinematics: &Kinematics, placed: &Placed, q: &[f64], u: &[f64], applied: &AppliedForces, gravity: bool) -> Result<Solved, ForwardDynamicsError> {
        let own = &self.geometry.multibody;
        contacted.gravity = if gravity { own.gravity } else { Vec3::zeros() };
        contacted.links.truncate(own.links.len());
        let mut first_row = own.links.iter().map(BodyLink::rows).sum::<usize>();
        let mut contact_rows = Vec::new();
        let mut links = Vec::new();
        for (contact, placement) in self.contacts.iter().zip(placed) {
            let link = placement.map(|(point, held)| contact.link(kinematics, &point, &held)).filter(|link| link.rows() > 0);
            let rows = link.as_ref().map_or(0, BodyLink::rows);
            contact_rows.push(first_row..first_row + rows);
            first_row += rows;
            links.push(link);
        }
        contacted.links.extend(links.iter().flatten().cloned());
        let (udot, multipliers) = contacted.accelerations_with_multipliers(kinematics, q, u, &applied.loads, &applied.mobility)?;
        Ok(Solved { udot, multipliers, contact_rows, links })
    }
}

/// One contributor's solution.
struct Solved {
    udot: Vec<f64>,
    multipliers: DVector<f64>,
    /// Each contact's rows among the multipliers.
    contact_rows: Vec<std::ops::Range<usize>>,
    /// Each contact's link, `None` where it holds nothing.
    links: Vec<Option<BodyLink>>,
}

impl Solved {
    /// The multipliers of contact `k`'s held rows.
    fn contact_multipliers(&self, k: usize) -> &[f64] {
        &self.multipliers.as_slice()[self.contact_rows[k].clone()]
    }
}

/// The tables' rows as they are recorded.
struct Recorder {
    /// The coordinates and bodies reported ([`Multibody`] indices), and whether the mass center is.
    reported: (Vec<usize>, Vec<usize>, bool),
    /// The model's mass, kg.
    mass: f64,
    /// One row-major value list per coordinate, per body, for the mass center, for the reactions.
    coordinates: Vec<Vec<f64>>,
    bodies: Vec<Vec<f64>>,
    center_of_mass: Vec<f64>,
    reactions: Vec<f64>,
}

impl Recorder {
    fn new(multibody: &Multibody, coordinates: Vec<usize>, bodies: Vec<usize>, center_of_mass: bool) -> Recorder {
        let values = (vec![Vec::new(); coordinates.len()], vec![Vec::new(); bodies.len()]);
        let mass = multibody.bodies.iter().map(|b| b.mass).sum();
        Recorder { reported: (coordinates, bodies, center_of_mass), mass, coordinates: values.0, bodies: values.1, center_of_mass: Vec::new(), reactions: Vec::new() }
    }

    /// Starts a row at `time` (s).
    fn start(&mut self, time: f64) {
        for values in self.coordinates.iter_mut().chain(self.bodies.iter_mut()).chain([&mut self.center_of_mass, &mut self.reactions]) {
            values.push(time);
        }
    }

    /// Appends one contributor's values, solved at the pose `kinematics` holds (`q`) with speeds
    /// `u`: each coordinate's u̇, each body's mass center and angular acceleration, the mass
    /// center's, the contacts' reactions.
    fn record(&mut self, run: &Run, kinematics: &Kinematics, solved: &Solved, q: &[f64], u: &[f64]) {
        let multibody = &run.geometry.multibody;
        let angle = if run.setup.in_degrees { 1f64.to_degrees() } else { 1.0 };
        for (values, &c) in self.coordinates.iter_mut().zip(&self.reported.0) {
            values.push(solved.udot[c] * angle);
        }
        let motions = multibody.body_motions(&MotionState { q, u, udot: &solved.udot });
        let center = |b: usize| motions[b].point_acceleration(&multibody.bodies[b].mass_center);
        for (values, &b) in self.bodies.iter_mut().zip(&self.reported.1) {
            values.extend(center(b).iter());
            values.extend(motions[b].angular_acceleration().iter().map(|a| a * angle));
        }
        let weighted: Vec3 = (0..multibody.bodies.len()).map(|b| multibody.bodies[b].mass * center(b)).sum::<Vec3>() / self.mass;
        self.center_of_mass.extend(weighted.iter());
        for (k, contact) in run.contacts.iter().enumerate() {
            match &solved.links[k] {
                Some(link) => contact.record(link, kinematics, &DVector::from_column_slice(solved.contact_multipliers(k)), &mut self.reactions),
                None => self.reactions.extend([0.0; 12]),
            }
        }
    }

    /// The tables, named by their file suffixes: each coordinate's, each body's, the mass
    /// center's (if reported), the reactions' (if reported).
    fn tables(self, run: &Run) -> Result<Vec<(String, StorageTable)>, InducedAccelerationsError> {
        let multibody = &run.geometry.multibody;
        let (coordinates, bodies, center_of_mass) = &self.reported;
        let names: Vec<&str> = run.contributors.iter().map(|(name, _)| name.as_str()).collect();
        let labels = |suffixes: &[&str]| -> Vec<String> { std::iter::once("time".to_string()).chain(names.iter().flat_map(|n| suffixes.iter().map(move |s| format!("{n}{s}")))).collect() };
        let mut tables = Vec::new();
        for (values, &c) in self.coordinates.into_iter().zip(coordinates) {
            let name = &multibody.coordinates[c].name;
            tables.push((name.clone(), StorageTable::new(name, labels(&[""]), values)?.with_in_degrees(run.setup.in_degrees)));
        }
        for (values, &b) in self.bodies.into_iter().zip(bodies) {
            let name = &multibody.bodies[b].name;
            tables.push((name.clone(), StorageTable::new(name, labels(&["_X", "_Y", "_Z", "_Ox", "_Oy", "_Oz"]), values)?.with_in_degrees(false)));
        }
        if *center_of_mass {
            tables.push((CENTER_OF_MASS.into(), StorageTable::new(CENTER_OF_MASS, labels(&["_X", "_Y", "_Z"]), self.center_of_mass)?.with_in_degrees(false)));
        }
        if run.setup.report_constraint_reactions {
            let records: Vec<String> = run.contacts.iter().flat_map(|c| c.record_labels(multibody)).collect();
            let mut reaction_labels = vec!["time".to_string()];
            reaction_labels.extend(names.iter().flat_map(|n| records.iter().map(move |r| format!("{n}_{r}"))));
            let name = "induced_constraint_reactions";
            tables.push((name.into(), StorageTable::new(name, reaction_labels, self.reactions)?.with_in_degrees(false)));
        }
        Ok(tables)
    }
}
