//! Tables: OpenSim `.sto`/`.mot` storage files and `.trc` marker trajectories.
//!
//! Reading keeps every value bit-exact and writing uses the shortest text that reads back to
//! the same bits. Units are explicit: [`StorageTable::in_degrees`] says how angles are stored
//! and [`MarkerTable::units`] how lengths are; conversions ([`StorageTable::to_radians`],
//! [`MarkerTable::in_meters`]) return new tables. Errors name the file and the 1-based line.

pub mod error;
pub mod storage;
mod text;
pub mod trc;
pub mod units;

pub use error::TableError;
pub use storage::StorageTable;
pub use trc::{MarkerTable, TrcHeader};
pub use units::LengthUnit;
