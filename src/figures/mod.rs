//! Figures: charts of what a command computed, drawn as SVG for a report — a functional fit's
//! knee moments and feasible sets, or any columns of OpenSim tables.

mod chart;
mod functional;
mod table;

pub use chart::{render, Chart, Mark, Series, Tone, SIZE};
pub use functional::{diagnosis_figures, feasible_set_figures, moment_figures};
pub use table::{table_chart, TableSeries};

/// A drawn figure and the file name it is written under (no folder).
#[derive(Debug, Clone, PartialEq)]
pub struct Figure {
    pub file_name: String,
    pub svg: String,
}

/// Why a figure could not be drawn.
#[derive(Debug, thiserror::Error)]
pub enum FigureError {
    #[error("figure {chart:?}: no finite point to draw")]
    NoData { chart: String },
    #[error("figure {chart:?}: drawing failed: {reason}")]
    Draw { chart: String, reason: String },
    #[error("{0}")]
    Input(String),
}
