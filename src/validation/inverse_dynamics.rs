//! Inverse dynamics against OpenSim 4.6's `InverseDynamicsSolver` at random states
//! (`fixtures/golden/inverse_dynamics/<model>.csv`, written by `oracle/gen_inverse_dynamics.py`:
//! state, coordinate, q, u, udot, generalized_force; the model's forces off, gravity on).

use std::path::Path;

use super::geometry::Worst;
use super::golden::{GoldenError, GoldenTable};
use crate::mechanics::{MotionState, Multibody};

/// The worst generalized-force error relative to max(1, |τ|) (N·m or N), and its state and
/// coordinate.
pub fn compare_inverse_dynamics(multibody: &Multibody, golden: &Path) -> Result<Worst, GoldenError> {
    let table = GoldenTable::read(golden)?;
    let n = multibody.coordinates.len();
    if table.rows.is_empty() || table.rows.len() % n != 0 {
        return Err(table.error_at(0, format!("expected whole states of {n} coordinates, found {} rows", table.rows.len())));
    }
    let mut worst = Worst::default();
    for first in (0..table.rows.len()).step_by(n) {
        let column = |name: &str| (first..first + n).map(|row| table.number_at(row, name)).collect::<Result<Vec<f64>, _>>();
        for (offset, coordinate) in multibody.coordinates.iter().enumerate() {
            let named = table.text_at(first + offset, "coordinate")?;
            if named != coordinate.name {
                return Err(table.error_at(first + offset, format!("expected coordinate {}, found {named}", coordinate.name)));
            }
        }
        let (q, u, udot, expected) = (column("q")?, column("u")?, column("udot")?, column("generalized_force")?);
        let forces = multibody.inverse_dynamics(&MotionState { q: &q, u: &u, udot: &udot }, &[]);
        for (c, (force, expected)) in forces.iter().zip(&expected).enumerate() {
            let state = table.text_at(first, "state")?;
            worst.update((force - expected).abs() / expected.abs().max(1.0), || format!("state {state} / {}", multibody.coordinates[c].name));
        }
    }
    Ok(worst)
}
