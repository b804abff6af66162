//! Kinematics and muscle geometry against OpenSim's goldens in a `geometry/<model>/` folder:
//! `poses.csv`, `bodies.csv`, `markers.csv`, `lengths.csv`, `muscle_coordinates.csv`,
//! `moment_arms.csv` (see the reference README for their meaning).

use std::collections::{BTreeSet, HashMap};
use std::path::Path;

use super::golden::{GoldenError, GoldenPoses, GoldenTable};
use crate::mechanics::{Kinematics, MuscleGeometry, PathScratch, Vec3};

/// The worst absolute error of one quantity and where it occurred.
#[derive(Debug, Clone, Default)]
pub struct Worst {
    pub error: f64,
    /// "pose / item" of the worst case.
    pub at: String,
    /// Values compared.
    pub count: usize,
}

impl Worst {
    pub(super) fn update(&mut self, error: f64, at: impl FnOnce() -> String) {
        self.count += 1;
        if error > self.error || error.is_nan() {
            self.error = if error.is_nan() { f64::INFINITY } else { error };
            self.at = at();
        }
    }
}

/// What a comparison found.
#[derive(Debug, Clone, Default)]
pub struct GeometryComparison {
    /// m.
    pub body_positions: Worst,
    /// Rotation matrix entries.
    pub body_rotations: Worst,
    /// m.
    pub markers: Worst,
    /// m.
    pub lengths: Worst,
    /// m (or m/m).
    pub moment_arms: Worst,
    /// (muscle, coordinate) pairs OpenSim evaluated that our span misses, or the reverse.
    pub span_mismatches: Vec<String>,
    /// Muscles not compared, with the reason.
    pub skipped: Vec<String>,
}

/// Compares `geometry` with the goldens in `folder`. Muscles whose paths wrap over objects
/// osim-tune does not wrap over ([`crate::mechanics::GeometryPath::ignored_wraps`]) are skipped
/// (and listed).
pub fn compare_geometry(geometry: &MuscleGeometry, folder: &Path) -> Result<GeometryComparison, GoldenError> {
    let multibody = &geometry.multibody;
    let poses = GoldenPoses::read(&folder.join("poses.csv"), multibody)?;
    let mut comparison = GeometryComparison::default();
    let skipped: BTreeSet<usize> = (0..geometry.paths.len()).filter(|&m| !geometry.paths[m].ignored_wraps.is_empty()).collect();
    comparison.skipped = skipped.iter().map(|&m| format!("{} (wrapping)", geometry.paths[m].name)).collect();
    let pairs = moment_arm_pairs(geometry, folder, &mut comparison)?;
    let mut evaluator = Evaluator { geometry, kinematics: multibody.kinematics(), scratch: PathScratch::default(), q: Vec::new() };
    for table in ["bodies.csv", "markers.csv", "lengths.csv", "moment_arms.csv"] {
        let Some(table) = GoldenTable::read_optional(&folder.join(table))? else { continue };
        let mut by_pose: HashMap<&str, Vec<usize>> = HashMap::new();
        for (r, row) in table.rows.iter().enumerate() {
            by_pose.entry(row[0].as_str()).or_default().push(r);
        }
        for id in &poses.ids {
            let Some(rows) = by_pose.get(id.as_str()) else { continue };
            evaluator.pose(&poses.values[id]);
            for &r in rows {
                evaluator.compare_row(&table, r, &skipped, &pairs, &mut comparison)?;
            }
        }
    }
    Ok(comparison)
}

/// Reads `muscle_coordinates.csv` and checks it against each path's span.
fn moment_arm_pairs(geometry: &MuscleGeometry, folder: &Path, comparison: &mut GeometryComparison) -> Result<BTreeSet<(usize, usize)>, GoldenError> {
    let multibody = &geometry.multibody;
    let table = GoldenTable::read(&folder.join("muscle_coordinates.csv"))?;
    let mut golden = BTreeSet::new();
    for row in &table.rows {
        let m = geometry.path_index(&row[0]).ok_or_else(|| format_error(folder, &format!("muscle {} is not in the model", row[0])))?;
        let c = multibody.coordinate_index(&row[1]).ok_or_else(|| format_error(folder, &format!("coordinate {} is not in the model", row[1])))?;
        golden.insert((m, c));
    }
    for (m, path) in geometry.paths.iter().enumerate() {
        for &c in &path.spanned {
            if !golden.contains(&(m, c)) {
                comparison.span_mismatches.push(format!("{} spans {} (OpenSim: no)", path.name, multibody.coordinates[c].name));
            }
        }
    }
    for &(m, c) in &golden {
        if !geometry.paths[m].spanned.contains(&c) {
            comparison.span_mismatches.push(format!("{} does not span {} (OpenSim: yes)", geometry.paths[m].name, multibody.coordinates[c].name));
        }
    }
    Ok(golden)
}

fn format_error(folder: &Path, problem: &str) -> GoldenError {
    GoldenError::Format { file: folder.into(), line: 1, problem: problem.into() }
}

/// Evaluates one pose at a time.
struct Evaluator<'g> {
    geometry: &'g MuscleGeometry,
    kinematics: Kinematics,
    scratch: PathScratch,
    q: Vec<f64>,
}

impl Evaluator<'_> {
    fn pose(&mut self, q: &[f64]) {
        self.q.clear();
        self.q.extend_from_slice(q);
        self.geometry.multibody.realize(&self.q, &mut self.kinematics);
    }

    /// Compares one row of a golden table (its kind told by its header).
    fn compare_row(
        &mut self,
        table: &GoldenTable,
        r: usize,
        skipped: &BTreeSet<usize>,
        pairs: &BTreeSet<(usize, usize)>,
        comparison: &mut GeometryComparison,
    ) -> Result<(), GoldenError> {
        let (geometry, multibody) = (self.geometry, &self.geometry.multibody);
        let row = &table.rows[r];
        let unknown = |what: &str, name: &str| GoldenError::Format { file: table.file.clone(), line: r + 2, problem: format!("{what} {name} is not in the model") };
        let vector = |first: usize| -> Result<Vec3, GoldenError> { Ok(Vec3::new(table.number(r, first)?, table.number(r, first + 1)?, table.number(r, first + 2)?)) };
        match table.header[1].as_str() {
            "body" => {
                let b = multibody.body_index(&row[1]).ok_or_else(|| unknown("body", &row[1]))?;
                let x = &self.kinematics.bodies[b];
                let at = || format!("{} / {}", row[0], row[1]);
                comparison.body_positions.update((x.translation - vector(2)?).amax(), at);
                for k in 0..9 {
                    comparison.body_rotations.update((x.rotation[(k / 3, k % 3)] - table.number(r, 5 + k)?).abs(), at);
                }
            }
            "marker" => {
                let k = multibody.markers.iter().position(|m| m.name == row[1]).ok_or_else(|| unknown("marker", &row[1]))?;
                let error = (self.kinematics.marker_location(multibody, k) - vector(2)?).amax();
                comparison.markers.update(error, || format!("{} / {}", row[0], row[1]));
            }
            "muscle" => {
                let m = geometry.path_index(&row[1]).ok_or_else(|| unknown("muscle", &row[1]))?;
                let c = multibody.coordinate_index(&row[2]).ok_or_else(|| unknown("coordinate", &row[2]))?;
                if skipped.contains(&m) || !pairs.contains(&(m, c)) {
                    return Ok(());
                }
                let mut moment_arm = [0.0];
                geometry.paths[m].moment_arms(multibody, &self.kinematics, &self.q, &mut self.scratch, &[c], &mut moment_arm);
                let error = (moment_arm[0] - table.number(r, 3)?).abs();
                comparison.moment_arms.update(error, || format!("{} / {} about {}", row[0], row[1], row[2]));
            }
            _ => {
                for (column, name) in table.header.iter().enumerate().skip(1) {
                    let m = geometry.path_index(name).ok_or_else(|| unknown("muscle", name))?;
                    if skipped.contains(&m) {
                        continue;
                    }
                    let length = geometry.paths[m].length(&self.kinematics, &self.q, &mut self.scratch);
                    comparison.lengths.update((length - table.number(r, column)?).abs(), || format!("{} / {name}", row[0]));
                }
            }
        }
        Ok(())
    }
}
