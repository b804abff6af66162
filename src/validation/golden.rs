//! Golden tables: the CSV files OpenSim 4.6 wrote through its Python bindings (one header line,
//! comma separated, floats as shortest round-trip decimals).

use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// Errors reading a golden table.
#[derive(Debug, thiserror::Error)]
pub enum GoldenError {
    #[error("{}: {source}", file.display())]
    Io { file: PathBuf, source: std::io::Error },
    #[error("{}:{line}: {problem}", file.display())]
    Format { file: PathBuf, line: usize, problem: String },
}

/// A CSV table kept as text.
#[derive(Debug, Clone)]
pub struct GoldenTable {
    pub file: PathBuf,
    pub header: Vec<String>,
    pub rows: Vec<Vec<String>>,
}

impl GoldenTable {
    pub fn read(file: &Path) -> Result<GoldenTable, GoldenError> {
        let text = std::fs::read_to_string(file).map_err(|source| GoldenError::Io { file: file.into(), source })?;
        let mut lines = text.lines();
        let header: Vec<String> = lines.next().unwrap_or_default().split(',').map(String::from).collect();
        let mut rows = Vec::new();
        for (index, line) in lines.enumerate() {
            let row: Vec<String> = line.split(',').map(String::from).collect();
            if row.len() != header.len() {
                let problem = format!("expected {} fields, found {}", header.len(), row.len());
                return Err(GoldenError::Format { file: file.into(), line: index + 2, problem });
            }
            rows.push(row);
        }
        Ok(GoldenTable { file: file.into(), header, rows })
    }

    /// Reads `file` when it exists.
    pub fn read_optional(file: &Path) -> Result<Option<GoldenTable>, GoldenError> {
        if file.exists() { GoldenTable::read(file).map(Some) } else { Ok(None) }
    }

    /// Field `column` of row `row` as a number.
    pub fn number(&self, row: usize, column: usize) -> Result<f64, GoldenError> {
        let text = &self.rows[row][column];
        text.parse().map_err(|_| GoldenError::Format { file: self.file.clone(), line: row + 2, problem: format!("{:?} is not a number", text) })
    }

    pub fn column(&self, name: &str) -> Result<usize, GoldenError> {
        self.header.iter().position(|h| h == name).ok_or_else(|| GoldenError::Format { file: self.file.clone(), line: 1, problem: format!("no column {name:?}") })
    }
}

/// `poses.csv`: coordinate values per pose id, by coordinate name.
pub struct GoldenPoses {
    pub ids: Vec<String>,
    pub coordinates: Vec<String>,
    pub values: HashMap<String, Vec<f64>>,
}

impl GoldenPoses {
    pub fn read(file: &Path) -> Result<GoldenPoses, GoldenError> {
        let table = GoldenTable::read(file)?;
        let mut values = HashMap::new();
        let mut ids = Vec::new();
        for (r, row) in table.rows.iter().enumerate() {
            let q = (1..table.header.len()).map(|c| table.number(r, c)).collect::<Result<Vec<_>, _>>()?;
            ids.push(row[0].clone());
            values.insert(row[0].clone(), q);
        }
        Ok(GoldenPoses { ids, coordinates: table.header[1..].to_vec(), values })
    }
}
