//! Predicted activations against EMG by cross-correlation (the thesis' ch. 7 check of inverse
//! simulations): per muscle, Pearson's correlation r(τ) between the prediction p(tᵢ) at its
//! rows and the EMG envelope e(tᵢ + τ), linearly interpolated, over the rows where both exist.
//! τ runs over multiples of the prediction's median row step up to ±`max_lag`; τ > 0 pairs a
//! prediction with later EMG.

use std::path::{Path, PathBuf};

use crate::io::table::StorageTable;
use super::signal::linear_interpolation;

/// Why the tables cannot be compared.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum EmgComparisonError {
    #[error("{}: no column named {column:?}{}", file.display(), suggestion(others))]
    MissingColumn { file: PathBuf, column: String, others: Vec<String> },
    #[error("{} and {} share no muscle name; pair them with --pair MUSCLE=CHANNEL", predicted.display(), emg.display())]
    NoPairs { predicted: PathBuf, emg: PathBuf },
    #[error("{}: needs at least 3 rows with strictly increasing times", file.display())]
    TooFewRows { file: PathBuf },
    #[error("max lag {0} s: expected a finite number ≥ 0")]
    MaxLag(f64),
}

fn suggestion(others: &[String]) -> String {
    if others.is_empty() { String::new() } else { format!(" (it has {})", others.join(", ")) }
}

/// One muscle's agreement.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct EmgCorrelation {
    pub muscle: String,
    pub channel: String,
    /// r at τ = 0; NaN when a signal is constant over the rows.
    pub at_zero_lag: f64,
    /// The largest r over the lags and its τ (s).
    pub best: f64,
    pub best_lag: f64,
    /// Rows compared at τ = 0.
    pub rows: usize,
}

/// A prediction table's column for `muscle`: the muscle's name, or OpenSim's state name
/// `/forceset/<muscle>/activation`.
fn prediction_column(table: &StorageTable, muscle: &str) -> Option<usize> {
    table.column_index(muscle).or_else(|| table.column_index(&format!("/forceset/{muscle}/activation")))
}

/// The muscles a prediction table has columns for (either naming).
fn predicted_muscles(table: &StorageTable) -> Vec<String> {
    table.labels()[1..].iter().map(|l| l.strip_prefix("/forceset/").and_then(|m| m.strip_suffix("/activation")).unwrap_or(l).to_string()).collect()
}

/// Correlates `predicted` (read from `predicted_file`) with `emg` (from `emg_file`) for each
/// (muscle, channel) of `pairs`, or — when `pairs` is empty — each predicted muscle the EMG
/// table has a column for.
pub fn correlate_with_emg(
    predicted: (&StorageTable, &Path),
    emg: (&StorageTable, &Path),
    pairs: &[(String, String)],
    max_lag: f64,
) -> Result<Vec<EmgCorrelation>, EmgComparisonError> {
    let ((p_table, p_file), (e_table, e_file)) = (predicted, emg);
    if !(max_lag >= 0.0 && max_lag.is_finite()) {
        return Err(EmgComparisonError::MaxLag(max_lag));
    }
    let pairs: Vec<(String, String)> = if pairs.is_empty() {
        predicted_muscles(p_table).into_iter().filter(|m| e_table.column_index(m).is_some()).map(|m| (m.clone(), m)).collect()
    } else {
        pairs.to_vec()
    };
    if pairs.is_empty() {
        return Err(EmgComparisonError::NoPairs { predicted: p_file.into(), emg: e_file.into() });
    }
    let (p_times, e_times) = (checked_times(p_table, p_file)?, checked_times(e_table, e_file)?);
    let step = median_step(&p_times);
    let lags: Vec<f64> = {
        let n = (max_lag / step + 1e-9).floor() as i64;
        (-n..=n).map(|k| k as f64 * step).collect()
    };
    pairs
        .iter()
        .map(|(muscle, channel)| {
            let missing = |file: &Path, column: &str, others: Vec<String>| EmgComparisonError::MissingColumn { file: file.into(), column: column.into(), others };
            let p = prediction_column(p_table, muscle).ok_or_else(|| missing(p_file, muscle, predicted_muscles(p_table)))?;
            let e = e_table.column_index(channel).ok_or_else(|| missing(e_file, channel, e_table.labels()[1..].to_vec()))?;
            let (p_values, e_values) = (p_table.column(&p_table.labels()[p]).unwrap_or_default(), e_table.column(&e_table.labels()[e]).unwrap_or_default());
            let correlation = |lag: f64| lagged_correlation(&p_times, &p_values, &e_times, &e_values, lag);
            let (at_zero_lag, rows) = correlation(0.0);
            let (best, best_lag) = lags.iter().map(|&lag| (correlation(lag).0, lag)).filter(|(r, _)| r.is_finite()).fold((f64::NAN, 0.0), |b, c| if b.0.is_nan() || c.0 > b.0 { c } else { b });
            Ok(EmgCorrelation { muscle: muscle.clone(), channel: channel.clone(), at_zero_lag, best, best_lag, rows })
        })
        .collect()
}

fn checked_times(table: &StorageTable, file: &Path) -> Result<Vec<f64>, EmgComparisonError> {
    let times = table.times();
    if times.len() < 3 || times.windows(2).any(|w| w[1] <= w[0]) {
        return Err(EmgComparisonError::TooFewRows { file: file.into() });
    }
    Ok(times)
}

fn median_step(times: &[f64]) -> f64 {
    let mut steps: Vec<f64> = times.windows(2).map(|w| w[1] - w[0]).collect();
    steps.sort_by(f64::total_cmp);
    steps[steps.len() / 2]
}

/// (r, rows) between p at its times and e interpolated at those times + `lag`, over the rows
/// whose shifted time lies within e's times.
fn lagged_correlation(p_times: &[f64], p: &[f64], e_times: &[f64], e: &[f64], lag: f64) -> (f64, usize) {
    let (first, last) = (e_times[0], e_times[e_times.len() - 1]);
    let pairs: Vec<(f64, f64)> = p_times.iter().zip(p).filter(|(&t, _)| (first..=last).contains(&(t + lag))).map(|(&t, &v)| (v, linear_interpolation(e_times, e, t + lag))).collect();
    (pearson(&pairs), pairs.len())
}

/// Pearson's r of the pairs; NaN for fewer than 3 or a constant signal.
fn pearson(pairs: &[(f64, f64)]) -> f64 {
    let n = pairs.len() as f64;
    if pairs.len() < 3 {
        return f64::NAN;
    }
    let (mx, my) = (pairs.iter().map(|p| p.0).sum::<f64>() / n, pairs.iter().map(|p| p.1).sum::<f64>() / n);
    let (mut sxy, mut sxx, mut syy) = (0.0, 0.0, 0.0);
    for &(x, y) in pairs {
        sxy += (x - mx) * (y - my);
        sxx += (x - mx) * (x - mx);
        syy += (y - my) * (y - my);
    }
    if sxx == 0.0 || syy == 0.0 { f64::NAN } else { sxy / (sxx * syy).sqrt() }
}
