//! What inverse kinematics reports per frame, and the tables OpenSim 4.6 writes: the coordinates
//! (`<trial>_ik.mot`), the marker errors (`<trial>_ik_marker_errors.sto`) and the model's marker
//! locations (`<trial>_ik_model_marker_locations.sto`).

use super::tasks::TrackedMarker;
use crate::io::table::{StorageTable, TableError};
use crate::mechanics::{Multibody, Vec3};
use crate::model::MotionType;
use crate::solvers::least_squares::LeastSquaresStatus;

/// Marker errors of a frame, as OpenSim's `InverseKinematicsTool` computes them: over all
/// markers in use, a marker without data counting 0 (Simbody's `findCurrentMarkerErrorSquared`)
/// but still counting in the RMS's denominator; weights play no part.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MarkerErrors {
    /// Σ‖x_i − x̂_i‖², m² (`total_squared_error`).
    pub total_squared: f64,
    /// √(total / markers in use), m (`marker_error_RMS`).
    pub rms: f64,
    /// Largest distance, m (`marker_error_max`).
    pub max: f64,
    /// Index (into the markers in use) of the first marker with the largest error; `None` when
    /// every error is 0.
    pub worst: Option<usize>,
}

impl MarkerErrors {
    pub(super) fn measure(markers: &[TrackedMarker], observed: &[Option<Vec3>], location: impl Fn(&TrackedMarker) -> Vec3) -> MarkerErrors {
        let (mut total_squared, mut max_squared, mut worst) = (0.0, 0.0, None);
        for (i, (marker, observation)) in markers.iter().zip(observed).enumerate() {
            let Some(observation) = observation else { continue };
            let squared = (location(marker) - observation).norm_squared();
            total_squared += squared;
            if squared > max_squared {
                max_squared = squared;
                worst = Some(i);
            }
        }
        let rms = if markers.is_empty() { 0.0 } else { (total_squared / markers.len() as f64).sqrt() };
        MarkerErrors { total_squared, rms, max: max_squared.sqrt(), worst }
    }
}

/// One solved frame.
#[derive(Debug, Clone, PartialEq)]
pub struct IkFrame {
    /// Index of the trial frame (from 0).
    pub frame: usize,
    /// s.
    pub time: f64,
    /// Every coordinate (rad or m), in [`Multibody::coordinates`] order.
    pub q: Vec<f64>,
    pub errors: MarkerErrors,
    /// Markers in use without data in this frame (indices into the markers in use).
    pub missing_markers: Vec<usize>,
    /// The minimised objective (Simbody's assembler goal, see `frame`).
    pub objective: f64,
    /// Gauss–Newton iterations.
    pub iterations: usize,
    pub status: LeastSquaresStatus,
}

/// The solved frames of a trial.
#[derive(Debug, Clone, PartialEq)]
pub struct IkSolution {
    /// Markers in use, in trial column order.
    pub markers: Vec<String>,
    /// Coordinate names, in [`Multibody::coordinates`] order.
    pub coordinates: Vec<String>,
    pub frames: Vec<IkFrame>,
}

impl IkSolution {
    /// Frames whose minimisation did not converge.
    pub fn unconverged(&self) -> impl Iterator<Item = &IkFrame> {
        self.frames.iter().filter(|f| f.status != LeastSquaresStatus::Converged)
    }

    /// The name of frame `frame`'s worst marker.
    pub fn worst_marker(&self, frame: &IkFrame) -> Option<&str> {
        frame.errors.worst.map(|i| self.markers[i].as_str())
    }

    /// OpenSim's IK motion: table `Coordinates`, `inDegrees=yes`, its two comment lines, a
    /// column per coordinate in `CoordinateSet` order; rotational coordinates in degrees
    /// (coupled and translational ones as they are, as OpenSim converts only rotational ones).
    pub fn motion_table(&self, multibody: &Multibody) -> Result<StorageTable, TableError> {
        let labels = std::iter::once("time".to_string()).chain(self.coordinates.iter().cloned()).collect();
        let rotational: Vec<bool> = multibody.coordinates.iter().map(|c| c.motion_type == MotionType::Rotational).collect();
        let mut values = Vec::with_capacity(self.frames.len() * (self.coordinates.len() + 1));
        for frame in &self.frames {
            values.push(frame.time);
            values.extend(frame.q.iter().zip(&rotational).map(|(q, r)| if *r { q.to_degrees() } else { *q }));
        }
        StorageTable::new("Coordinates", labels, values)?
            .with_in_degrees(true)
            .with_comment("")?
            .with_comment("Units are S.I. units (second, meters, Newtons, ...)")?
            .with_comment("If the header above contains a line with 'inDegrees', this indicates whether rotational values are in degrees (yes) or radians (no).")?
            .with_comment("")
    }

    /// OpenSim's `Model Marker Locations from IK` table (`report_marker_locations`): each
    /// tracked marker's `<marker>_tx`, `_ty`, `_tz` in ground (m) at each frame's pose,
    /// `inDegrees=no`.
    pub fn marker_locations_table(&self, multibody: &Multibody) -> Result<StorageTable, TableError> {
        let indices: Vec<usize> = self.markers.iter().filter_map(|name| multibody.markers.iter().position(|m| &m.name == name)).collect();
        let labels = std::iter::once("time".to_string()).chain(self.markers.iter().flat_map(|name| ["tx", "ty", "tz"].map(|axis| format!("{name}_{axis}")))).collect();
        let mut kinematics = multibody.kinematics();
        let mut values = Vec::with_capacity(self.frames.len() * (3 * indices.len() + 1));
        for frame in &self.frames {
            multibody.realize(&frame.q, &mut kinematics);
            values.push(frame.time);
            for &k in &indices {
                values.extend(kinematics.marker_location(multibody, k).iter());
            }
        }
        Ok(StorageTable::new("Model Marker Locations from IK", labels, values)?.with_in_degrees(false))
    }

    /// OpenSim's `Model Marker Errors from IK` table: `total_squared_error` (m²),
    /// `marker_error_RMS` and `marker_error_max` (m) per frame, `inDegrees=no`.
    pub fn marker_errors_table(&self) -> Result<StorageTable, TableError> {
        let labels = ["time", "total_squared_error", "marker_error_RMS", "marker_error_max"].map(String::from).to_vec();
        let values = self.frames.iter().flat_map(|f| [f.time, f.errors.total_squared, f.errors.rms, f.errors.max]).collect();
        Ok(StorageTable::new("Model Marker Errors from IK", labels, values)?.with_in_degrees(false))
    }
}
