//! A chart of OpenSim table columns (`.sto`, `.mot`) against time or another column: one colour
//! per column, one line style per table, so the same column of two tables (ours and OpenSim's)
//! overlays.

use std::path::Path;

use crate::io::table::StorageTable;

use super::{Chart, FigureError, Mark, Series, Tone};

/// A table to draw from and the name it is shown under.
pub struct TableSeries<'a> {
    pub file: &'a Path,
    pub table: &'a StorageTable,
}

/// Line styles of the first, second, … table; later tables repeat them.
const TABLE_MARKS: [Mark; 3] = [Mark::Line, Mark::Dashed, Mark::Circles];

/// The chart of `columns` of every table against `x` (a column label, or the time column when
/// `None`). Errors name the file that lacks a column, with its labels.
pub fn table_chart(tables: &[TableSeries], columns: &[String], x: Option<&str>, title: &str, y_label: &str) -> Result<Chart, FigureError> {
    let mut series = Vec::new();
    for (k, source) in tables.iter().enumerate() {
        let abscissa = match x {
            None => source.table.times(),
            Some(label) => column(source, label)?,
        };
        for (c, label) in columns.iter().enumerate() {
            let name = if tables.len() > 1 { format!("{}: {label}", file_name(source.file)) } else { label.clone() };
            let points = abscissa.iter().copied().zip(column(source, label)?).collect();
            series.push(Series::new(name, points, TABLE_MARKS[k % TABLE_MARKS.len()], Tone::Palette(c)));
        }
    }
    Ok(Chart { title: title.into(), x_label: x.unwrap_or("time (s)").into(), y_label: y_label.into(), series })
}

fn column(source: &TableSeries, label: &str) -> Result<Vec<f64>, FigureError> {
    if source.table.column_indices(label).len() > 1 {
        return Err(FigureError::Input(format!("{}: several columns are labelled {label:?}; expected one", source.file.display())));
    }
    source.table.column(label).ok_or_else(|| {
        let labels = source.table.labels();
        let shown: Vec<&str> = labels.iter().take(12).map(String::as_str).collect();
        let more = if labels.len() > shown.len() { format!(", … ({} in all)", labels.len()) } else { String::new() };
        FigureError::Input(format!("{}: no column {label:?}; expected one of {}{more}", source.file.display(), shown.join(", ")))
    })
}

fn file_name(file: &Path) -> String {
    file.file_name().map_or_else(|| file.display().to_string(), |name| name.to_string_lossy().into_owned())
}
