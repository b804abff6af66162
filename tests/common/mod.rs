//! Helpers shared by the integration tests: fixture paths and document lists.
#![allow(dead_code)]

use std::path::{Path, PathBuf};

pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

pub fn fixture(relative: &str) -> PathBuf {
    root().join("fixtures").join(relative)
}

/// Every `.osim` and OpenSim setup `.xml` shipped in `models/` and `fixtures/`.
pub fn opensim_documents() -> Vec<PathBuf> {
    let mut found = Vec::new();
    collect(&root().join("models"), &mut found);
    collect(&root().join("fixtures"), &mut found);
    found.sort();
    assert!(found.len() >= 15, "expected the bundled models and subject01 setups, found {found:?}");
    found
}

fn collect(directory: &Path, found: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(directory).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            collect(&path, found);
        } else if matches!(path.extension().and_then(|e| e.to_str()), Some("osim" | "xml")) {
            found.push(path);
        }
    }
}

/// `nominal` with L_opt and L_ts from the `true_parameters` of `folder`'s `ground_truth.json`
/// (a public dynamometry subject).
pub fn true_parameters(folder: &Path, nominal: Vec<osim_tune::tuning::functional::MuscleParameters>) -> Vec<osim_tune::tuning::functional::MuscleParameters> {
    osim_tune::validation::functional::GroundTruth::read(folder).unwrap().parameters(&nominal).unwrap()
}

/// Runs the `osim-tune` binary; returns (exit code, stdout, stderr).
pub fn osim_tune(arguments: &[&str]) -> (i32, String, String) {
    let output = std::process::Command::new(env!("CARGO_BIN_EXE_osim-tune")).args(arguments).output().unwrap();
    (
        output.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&output.stdout).into_owned(),
        String::from_utf8_lossy(&output.stderr).into_owned(),
    )
}

/// Golden CSV rows read by column name.
pub mod golden_rows {
    use osim_tune::validation::GoldenTable;

    /// One row of a golden table.
    pub struct Row<'a> {
        table: &'a GoldenTable,
        index: usize,
    }

    impl Row<'_> {
        pub fn number(&self, column: &str) -> f64 {
            self.table.number(self.index, self.table.column(column).unwrap()).unwrap()
        }

        pub fn text(&self, column: &str) -> &str {
            &self.table.rows[self.index][self.table.column(column).unwrap()]
        }
    }

    pub fn rows(table: &GoldenTable) -> impl Iterator<Item = Row<'_>> {
        (0..table.rows.len()).map(move |index| Row { table, index })
    }
}

/// The attributes of every `<tag …>` element of an SVG document, in document order.
pub fn svg_elements(svg: &str, tag: &str) -> Vec<std::collections::HashMap<String, String>> {
    let opening = format!("<{tag} ");
    svg.match_indices(&opening)
        .map(|(start, _)| {
            let element = &svg[start + opening.len()..start + svg[start..].find('>').unwrap()];
            element
                .split('"')
                .collect::<Vec<_>>()
                .chunks(2)
                .filter(|pair| pair.len() == 2)
                .map(|pair| (pair[0].trim().trim_end_matches('=').to_string(), pair[1].to_string()))
                .collect()
        })
        .collect()
}

/// The (x, y) pixel positions of an SVG element's `points` attribute (a polyline's vertices).
pub fn svg_points(element: &std::collections::HashMap<String, String>) -> Vec<(f64, f64)> {
    element["points"]
        .split_whitespace()
        .map(|pair| {
            let (x, y) = pair.split_once(',').unwrap();
            (x.parse().unwrap(), y.parse().unwrap())
        })
        .collect()
}

/// The affine map of data to pixels along one axis, fitted to the two data values farthest
/// apart and their pixels: `pixel = a + b·value`.
pub fn pixel_map(pairs: &[(f64, f64)]) -> impl Fn(f64) -> f64 {
    let low = pairs.iter().copied().min_by(|p, q| p.0.total_cmp(&q.0)).unwrap();
    let high = pairs.iter().copied().max_by(|p, q| p.0.total_cmp(&q.0)).unwrap();
    let slope = (high.1 - low.1) / (high.0 - low.0);
    move |value| low.1 + slope * (value - low.0)
}
