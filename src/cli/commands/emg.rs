//! `osim-tune emg PREDICTED.sto EMG.sto [--pair MUSCLE=CHANNEL,…] [--max-lag S] [--json]`

use std::path::Path;

use crate::analysis::{correlate_with_emg, EmgCorrelation};
use crate::cli::{Failure, Outcome};
use crate::io::table::StorageTable;

pub fn run(predicted: &Path, emg: &Path, pairs: &[String], max_lag: f64, json: bool) -> Result<Outcome, Failure> {
    let pairs = pairs
        .iter()
        .map(|p| match p.split_once('=') {
            Some((muscle, channel)) if !muscle.is_empty() && !channel.is_empty() => Ok((muscle.to_string(), channel.to_string())),
            _ => Err(format!("--pair {p:?}: expected MUSCLE=CHANNEL")),
        })
        .collect::<Result<Vec<_>, _>>()?;
    let (p_table, e_table) = (StorageTable::read(predicted)?, StorageTable::read(emg)?);
    let correlations = correlate_with_emg((&p_table, predicted), (&e_table, emg), &pairs, max_lag)?;
    if json {
        println!("{}", serde_json::to_string_pretty(&correlations)?);
    } else {
        print_table(&correlations, predicted, emg, max_lag);
    }
    Ok(Outcome::Success)
}

fn print_table(correlations: &[EmgCorrelation], predicted: &Path, emg: &Path, max_lag: f64) {
    println!("{} against {} (Pearson r; best over lags up to ±{max_lag} s, lag > 0: later EMG)", predicted.display(), emg.display());
    println!("{:<20} {:<20} {:>8} {:>8} {:>9} {:>6}", "muscle", "EMG channel", "r(0)", "best r", "lag (s)", "rows");
    for c in correlations {
        println!("{:<20} {:<20} {:>8.3} {:>8.3} {:>9.4} {:>6}", c.muscle, c.channel, c.at_zero_lag, c.best, c.best_lag, c.rows);
    }
}
