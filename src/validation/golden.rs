//! Golden tables: the CSV files OpenSim 4.6 wrote through its Python bindings (one header line,
//! comma separated, floats as shortest round-trip decimals).

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use crate::mechanics::Multibody;

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

    /// Field `name` of row `row` as a number.
    pub fn number_at(&self, row: usize, name: &str) -> Result<f64, GoldenError> {
        self.number(row, self.column(name)?)
    }

    /// Field `name` of row `row` as text.
    pub fn text_at(&self, row: usize, name: &str) -> Result<&str, GoldenError> {
        Ok(&self.rows[row][self.column(name)?])
    }

    /// An error at row `row` (0-based, after the header).
    pub fn error_at(&self, row: usize, problem: String) -> GoldenError {
        GoldenError::Format { file: self.file.clone(), line: row + 2, problem }
    }

    pub fn column(&self, name: &str) -> Result<usize, GoldenError> {
        self.header.iter().position(|h| h == name).ok_or_else(|| GoldenError::Format { file: self.file.clone(), line: 1, problem: format!("no column {name:?}") })
    }
}

/// `poses.csv`: coordinate values per pose id.
pub struct GoldenPoses {
    /// In file order.
    pub ids: Vec<String>,
    /// Per pose id, one value per coordinate of the model, in [`Multibody::coordinates`] order.
    pub values: HashMap<String, Vec<f64>>,
}

impl GoldenPoses {
    /// Reads `file`, whose columns must all be coordinates of `multibody`; coordinates the file
    /// lacks keep their default value.
    pub fn read(file: &Path, multibody: &Multibody) -> Result<GoldenPoses, GoldenError> {
        let table = GoldenTable::read(file)?;
        let columns: Vec<usize> = table.header[1..]
            .iter()
            .map(|name| {
                let problem = || format!("coordinate {name} is not in the model");
                multibody.coordinate_index(name).ok_or_else(|| GoldenError::Format { file: file.into(), line: 1, problem: problem() })
            })
            .collect::<Result<_, _>>()?;
        let mut values = HashMap::new();
        let mut ids = Vec::new();
        for (r, row) in table.rows.iter().enumerate() {
            let mut q = multibody.default_pose();
            for (column, &c) in columns.iter().enumerate() {
                q[c] = table.number(r, column + 1)?;
            }
            ids.push(row[0].clone());
            values.insert(row[0].clone(), q);
        }
        Ok(GoldenPoses { ids, values })
    }
}
