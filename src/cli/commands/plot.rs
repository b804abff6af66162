//! `osim-tune plot TABLE… --columns C,… -o FIG.svg`: table columns as an SVG chart.

use std::path::{Path, PathBuf};

use crate::cli::{create_output_folders, Failure, Outcome};
use crate::figures::{render, table_chart, TableSeries};
use crate::io::atomic::write_atomically;
use crate::io::table::StorageTable;

/// What to draw besides the tables.
pub struct Request {
    pub columns: Vec<String>,
    pub x: Option<String>,
    pub title: Option<String>,
    pub y_label: Option<String>,
}

pub fn run(files: &[PathBuf], request: &Request, output: &Path) -> Result<Outcome, Failure> {
    if !output.extension().is_some_and(|e| e.eq_ignore_ascii_case("svg")) {
        return Err(format!("{}: expected a .svg file name (the chart is written as SVG)", output.display()).into());
    }
    let inputs: Vec<&Path> = files.iter().map(PathBuf::as_path).collect();
    crate::io::atomic::ensure_not_an_input(output, &inputs)?;
    let tables = files.iter().map(|file| StorageTable::read(file)).collect::<Result<Vec<_>, _>>()?;
    let sources: Vec<TableSeries> = files.iter().zip(&tables).map(|(file, table)| TableSeries { file, table }).collect();
    let title = request.title.clone().unwrap_or_else(|| files.iter().map(|f| f.file_name().unwrap_or(f.as_os_str()).to_string_lossy()).collect::<Vec<_>>().join(" vs "));
    let y_label = request.y_label.clone().unwrap_or_else(|| match &request.columns[..] {
        [column] => column.clone(),
        _ => "value".into(),
    });
    let chart = table_chart(&sources, &request.columns, request.x.as_deref(), &title, &y_label)?;
    let svg = render(&chart)?;
    create_output_folders([output])?;
    write_atomically(output, svg.as_bytes(), &inputs)?;
    eprintln!("plot: {} series drawn; wrote {}", chart.series.len(), output.display());
    Ok(Outcome::Success)
}
