//! Scaled models compared with OpenSim's, component by component and property by property.

use crate::io::osim::OsimDocument;
use crate::review::{diff_flat, flatten, Difference, Tolerance};

/// The agreement the Scale step must reach: 1e-7 relative, or 1e-9 (m, kg, …) for values near 0.
pub const SCALED_MODEL_TOLERANCE: Tolerance = Tolerance { relative: 1e-7, absolute: 1e-9 };

/// Every difference between OpenSim's scaled model and ours beyond `tolerance`. Component paths
/// of ours are first renamed as OpenSim 4.6 writes them (a 4.0 generic model names a muscle's
/// path `geometrypath`; 4.6 writes `path`).
pub fn compare_scaled_models(opensim: &OsimDocument, ours: &OsimDocument, tolerance: Tolerance) -> Vec<Difference> {
    let ours = flatten(ours).renamed(as_written_by_opensim_46);
    diff_flat(&flatten(opensim), &ours, tolerance)
}

fn as_written_by_opensim_46(path: &str) -> String {
    path.split('/').map(|segment| if segment == "geometrypath" { "path" } else { segment }).collect::<Vec<_>>().join("/")
}
