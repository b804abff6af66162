//! OpenSim's `Storage` signal operations that its tools apply to coordinates before
//! differentiating them: `pad` (reflect and negate), `lowpassIIR` and `lowpassFIR` (resampled
//! first when the sampling is not uniform) and the GCV splines that resample and differentiate.

use crate::mechanics::Function;
use crate::model::FunctionSpec;

/// Largest number of samples `Storage::resample` makes (OpenSim's `MAX_RESAMPLE_SIZE`).
const MAX_RESAMPLE_SIZE: f64 = 100_000.0;
/// SimTK's `Eps`: the step irregularity above which `lowpassIIR` resamples.
const EPS: f64 = f64::EPSILON;

/// Samples of several signals at shared times (s), strictly increasing.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    pub times: Vec<f64>,
    /// One per signal, each as long as `times`.
    pub columns: Vec<Vec<f64>>,
}

/// Why a series cannot be processed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SignalError {
    #[error("times must increase strictly, but row {row} is at {time} s after {previous} s")]
    TimesNotIncreasing { row: usize, time: f64, previous: f64 },
    #[error("{needed} samples are needed, found {found}")]
    TooFewSamples { needed: usize, found: usize },
}

impl Series {
    /// Checks the times and the number of samples (`needed` at least).
    pub fn new(times: Vec<f64>, columns: Vec<Vec<f64>>, needed: usize) -> Result<Series, SignalError> {
        if times.len() < needed {
            return Err(SignalError::TooFewSamples { needed, found: times.len() });
        }
        increasing(&times)?;
        Ok(Series { times, columns })
    }

    /// What OpenSim's tools do to coordinates given a cutoff (Hz): pad by half the samples, then
    /// [`Series::lowpass`]; unchanged without one.
    pub fn filtered(self, cutoff: Option<f64>) -> Result<Series, SignalError> {
        match cutoff {
            Some(cutoff) => self.pad(self.times.len() / 2).lowpass(cutoff),
            None => Ok(self),
        }
    }

    /// `Storage::pad(n)`: n samples before and after, the times and each signal reflected about
    /// its end sample and negated (`Signal::Pad`) — for n not below the number of samples, padded
    /// again and again by as many as there are, less one, until n are added on each side.
    pub fn pad(&self, n: usize) -> Series {
        let padded = |signal: &[f64]| {
            let target = signal.len() + 2 * n;
            let mut padded = signal.to_vec();
            let mut pad = n.min(signal.len().saturating_sub(1));
            while padded.len() < target && pad > 0 {
                padded = reflect(&padded, pad);
                pad = ((target - padded.len()) / 2).min(padded.len() - 1);
            }
            padded
        };
        Series { times: padded(&self.times), columns: self.columns.iter().map(|c| padded(c)).collect() }
    }

    /// `Storage::lowpassIIR(cutoff)`: resampled at the smallest step by degree-5 GCV splines when
    /// the steps differ, then each signal through `Signal::LowpassIIR` (Hz).
    pub fn lowpass(&self, cutoff: f64) -> Result<Series, SignalError> {
        let (series, step) = self.uniform()?;
        if series.times.len() < 4 {
            return Err(SignalError::TooFewSamples { needed: 4, found: series.times.len() });
        }
        let columns = series.columns.iter().map(|c| butterworth(step, cutoff, c)).collect();
        Ok(Series { times: series.times, columns })
    }

    /// `Storage::lowpassFIR(order, cutoff)`: resampled at the smallest step as
    /// [`Series::lowpass`] does, then each signal through `Signal::LowpassFIR` — a windowed-sinc
    /// filter of 2·`order` + 1 taps (Hamming window, unit gain at 0 Hz) over the signal padded by
    /// `order` samples, cutoff in Hz; at least 2·`order` samples are needed.
    pub fn lowpass_fir(&self, order: usize, cutoff: f64) -> Result<Series, SignalError> {
        let (series, step) = self.uniform()?;
        if series.times.len() < 2 * order {
            return Err(SignalError::TooFewSamples { needed: 2 * order, found: series.times.len() });
        }
        let columns = series.columns.iter().map(|c| windowed_sinc(order, step, cutoff, c)).collect();
        Ok(Series { times: series.times, columns })
    }

    /// The series at a uniform step — itself, or resampled at its smallest step when the steps
    /// differ — and that step (s).
    fn uniform(&self) -> Result<(Series, f64), SignalError> {
        let n = self.times.len();
        let step = self.times.windows(2).map(|w| w[1] - w[0]).fold(f64::INFINITY, f64::min);
        let average = (self.times[n - 1] - self.times[0]) / (n - 1) as f64;
        if average - step > EPS { self.resample(step) } else { Ok((self.clone(), step)) }
    }

    /// Degree-5 interpolating GCV splines of each signal (`GCVSplineSet(5, storage)`).
    pub fn splines(&self) -> Result<Vec<Function>, SignalError> {
        self.columns.iter().map(|c| spline(5, &self.times, c)).collect()
    }

    /// `Storage::resample(step, 5)`: the splines sampled from the first time at `step`
    /// (accumulated, as `GCVSplineSet::constructStorage` steps) up to the last.
    fn resample(&self, step: f64) -> Result<(Series, f64), SignalError> {
        let (first, last) = (self.times[0], self.times[self.times.len() - 1]);
        let step = if (last - first) / step > MAX_RESAMPLE_SIZE { (last - first) / MAX_RESAMPLE_SIZE } else { step };
        let splines = self.splines()?;
        let mut times = Vec::new();
        let mut x = first;
        while x <= last {
            times.push(x);
            x += step;
        }
        let columns = splines.iter().map(|s| times.iter().map(|&t| s.value(t)).collect()).collect();
        Ok((Series { times, columns }, step))
    }
}

/// Checks that `times` increase strictly (the error names the 0-based row).
pub fn increasing(times: &[f64]) -> Result<(), SignalError> {
    match (1..times.len()).find(|&i| times[i].partial_cmp(&times[i - 1]) != Some(std::cmp::Ordering::Greater)) {
        Some(row) => Err(SignalError::TimesNotIncreasing { row, time: times[row], previous: times[row - 1] }),
        None => Ok(()),
    }
}

/// Linear interpolation of (times, values) at `t` (`Storage::getDataAtTime`: a row's own value
/// at its time, even when its neighbour is NaN), extended from the first or last two rows outside
/// the times; `times` increasing, at least two.
pub fn linear_interpolation(times: &[f64], values: &[f64], t: f64) -> f64 {
    let after = times.partition_point(|&x| x <= t).min(times.len() - 1).max(1);
    let (t0, t1) = (times[after - 1], times[after]);
    let w = (t - t0) / (t1 - t0);
    if w == 0.0 {
        values[after - 1]
    } else {
        values[after - 1] + w * (values[after] - values[after - 1])
    }
}

/// The rows OpenSim's tools solve for `range` (s): from the last time at or before
/// max(start, first time) to the last at or before min(end, last time) (`Storage::findIndex`);
/// `None` when the range misses the times.
pub fn rows_in_range(times: &[f64], range: [f64; 2]) -> Option<std::ops::RangeInclusive<usize>> {
    let (first, last) = (times[0], times[times.len() - 1]);
    let (start, end) = (range[0].max(first), range[1].min(last));
    if start > end {
        return None;
    }
    let index = |t: f64| times.iter().position(|&time| t < time).unwrap_or(times.len()).saturating_sub(1);
    Some(index(start)..=index(end))
}

/// No frame of a motion file lies in the requested time range.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{}: no frame lies in the time range {start}–{end} s (the frames span {first}–{last} s)", file.display())]
pub struct NoFramesInRange {
    pub file: std::path::PathBuf,
    /// The requested range, s.
    pub start: f64,
    pub end: f64,
    /// The file's first and last frame times, s.
    pub first: f64,
    pub last: f64,
}

/// [`rows_in_range`] of the frames at `times` (s) of `file`, or why there are none.
pub fn frames_in_range(file: &std::path::Path, times: &[f64], range: [f64; 2]) -> Result<std::ops::RangeInclusive<usize>, NoFramesInRange> {
    rows_in_range(times, range).ok_or_else(|| NoFramesInRange { file: file.into(), start: range[0], end: range[1], first: times[0], last: times[times.len() - 1] })
}

/// An interpolating GCV spline of `degree` through (times, values), as OpenSim builds one
/// (`GCVSpline(degree, n, x, y)`, error variance 0); the times must increase.
pub fn spline(degree: usize, times: &[f64], values: &[f64]) -> Result<Function, SignalError> {
    if times.len() <= degree {
        return Err(SignalError::TooFewSamples { needed: degree + 1, found: times.len() });
    }
    increasing(times)?;
    Ok(Function::new(&FunctionSpec::GCVSpline { degree, error_variance: 0.0, x: times.to_vec(), y: values.to_vec() }))
}

/// `Signal::Pad`: s[−k] = 2·s[0] − s[k] and s[n−1+k] = 2·s[n−1] − s[n−1−k], k = 1…`pad`.
fn reflect(signal: &[f64], pad: usize) -> Vec<f64> {
    let n = signal.len();
    let before = (1..=pad).rev().map(|k| 2.0 * signal[0] - signal[k]);
    let after = (1..=pad).map(|k| 2.0 * signal[n - 1] - signal[n - 1 - k]);
    before.chain(signal.iter().copied()).chain(after).collect()
}

/// `Signal::LowpassFIR`: y[n] = Σₖ c(k)·s[n − k] / Σₖ c(k), k = −`order`…`order`, c(k) =
/// sinc(k·ω·T)·ω·T/π · (0.54 + 0.46·cos(kπ/`order`)), ω = 2π·`cutoff` (Hz), T = `step` (s), s the
/// signal padded by `order` samples (`Signal::Pad`).
fn windowed_sinc(order: usize, step: f64, cutoff: f64, signal: &[f64]) -> Vec<f64> {
    use std::f64::consts::PI;
    let m = order as i64;
    let padded = reflect(signal, order);
    let w = 2.0 * PI * cutoff;
    let sinc = |x: f64| if x.abs() < 1e-8 { 1.0 } else { x.sin() / x };
    let coefficient = |k: i64| sinc(k as f64 * w * step) * step * w / PI * (0.54 + 0.46 * (k as f64 * PI / order as f64).cos());
    (0..signal.len() as i64)
        .map(|n| {
            let (sum, total) = (-m..=m).fold((0.0, 0.0), |(sum, total), k| {
                let c = coefficient(k);
                (sum + c * padded[(m + n - k) as usize], total + c)
            });
            sum / total
        })
        .collect()
}

/// `Signal::LowpassIIR`: a third-order Butterworth low-pass (bilinear transform with frequency
/// warping) run forward and then backward, sample step `step` (s), cutoff `cutoff` (Hz; lowered
/// to 0.49 of the sampling rate if it is not below half of it). The first three samples of each
/// pass are copied, as OpenSim does.
fn butterworth(step: f64, cutoff: f64, signal: &[f64]) -> Vec<f64> {
    let rate = 1.0 / step;
    let cutoff = if cutoff >= 0.5 * rate { 0.49 * rate } else { cutoff };
    let wa = (2.0 * std::f64::consts::PI * cutoff * step / 2.0).tan();
    let (wa2, wa3) = (wa * wa, wa * wa * wa);
    let denominator = (wa + 1.0) * (wa * wa + wa + 1.0);
    let a = [wa3 / denominator, 3.0 * wa3 / denominator, 3.0 * wa3 / denominator, wa3 / denominator];
    let b = [
        1.0,
        (3.0 * wa3 + 2.0 * wa2 - 2.0 * wa - 3.0) / denominator,
        (3.0 * wa3 - 2.0 * wa2 - 2.0 * wa + 3.0) / denominator,
        (wa - 1.0) * (wa2 - wa + 1.0) / denominator,
    ];
    let pass = |input: &[f64]| {
        let mut output = input.to_vec();
        for i in 3..input.len() {
            output[i] = a[0] * input[i] + a[1] * input[i - 1] + a[2] * input[i - 2] + a[3] * input[i - 3] - b[1] * output[i - 1] - b[2] * output[i - 2] - b[3] * output[i - 3];
        }
        output
    };
    let mut forward = pass(signal);
    forward.reverse();
    let mut both = pass(&forward);
    both.reverse();
    both
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn padding_reflects_and_negates_about_the_end_samples() {
        let padded = reflect(&[1.0, 2.0, 4.0, 7.0], 2);
        assert_eq!(padded, vec![-2.0, 0.0, 1.0, 2.0, 4.0, 7.0, 10.0, 12.0]);
    }

    /// A constant passes unchanged (unit DC gain) and a tone far above the cutoff is removed.
    /// `Signal::Pad` on an array shorter than the pad: padded by its length less one, then by
    /// what is still missing.
    #[test]
    fn a_pad_longer_than_the_signal_is_repeated() {
        let series = Series::new(vec![0.0, 1.0, 2.0], vec![vec![1.0, 2.0, 4.0]], 1).unwrap().pad(4);
        assert_eq!(series.times, vec![-4.0, -3.0, -2.0, -1.0, 0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0]);
        // Once by 2: [-2, 0 | 1 2 4 | 6, 7]; then by 2 more, about the new ends.
        assert_eq!(series.columns[0], vec![-5.0, -4.0, -2.0, 0.0, 1.0, 2.0, 4.0, 6.0, 7.0, 8.0, 10.0]);
    }

    /// The FIR filter passes a constant and a slow line unchanged in the middle, and removes a
    /// tone far above its cutoff.
    #[test]
    fn the_fir_filter_keeps_slow_signals_and_removes_a_high_tone() {
        let times: Vec<f64> = (0..400).map(|i| i as f64 * 0.01).collect();
        let slow: Vec<f64> = times.iter().map(|t| 2.0 + 0.5 * t).collect();
        let noisy: Vec<f64> = times.iter().zip(&slow).map(|(t, s)| s + (2.0 * std::f64::consts::PI * 40.0 * t).sin()).collect();
        let filtered = Series::new(times, vec![slow.clone(), noisy], 1).unwrap().lowpass_fir(50, 6.0).unwrap();
        for (i, expected) in slow.iter().enumerate().take(340).skip(60) {
            assert!((filtered.columns[0][i] - expected).abs() < 1e-12, "{i}");
            assert!((filtered.columns[1][i] - expected).abs() < 1e-3, "{i}: {}", filtered.columns[1][i] - expected);
        }
        let short = Series::new(vec![0.0, 0.1, 0.2], vec![vec![0.0; 3]], 1).unwrap();
        assert_eq!(short.lowpass_fir(2, 1.0), Err(SignalError::TooFewSamples { needed: 4, found: 3 }));
    }

    #[test]
    fn the_filter_keeps_a_constant_and_removes_a_high_tone() {
        let step = 0.01;
        let constant = butterworth(step, 6.0, &[2.5; 200]);
        assert!(constant.iter().all(|v| (v - 2.5).abs() < 1e-12));
        let tone: Vec<f64> = (0..400).map(|i| (2.0 * std::f64::consts::PI * 40.0 * i as f64 * step).sin()).collect();
        let filtered = butterworth(step, 6.0, &tone);
        assert!(filtered[100..300].iter().all(|v| v.abs() < 0.01), "{:?}", &filtered[100..110]);
    }

    #[test]
    fn irregular_steps_are_resampled_at_the_smallest() {
        let times = vec![0.0, 0.017, 0.033, 0.05, 0.067, 0.083, 0.1, 0.117];
        let series = Series::new(times.clone(), vec![times.iter().map(|t| 3.0 * t).collect()], 6).unwrap();
        let (resampled, step) = series.resample(0.016).unwrap();
        assert_eq!(step, 0.016);
        assert_eq!(resampled.times.len(), 8);
        for (t, v) in resampled.times.iter().zip(&resampled.columns[0]) {
            assert!((v - 3.0 * t).abs() < 1e-12);
        }
    }

    #[test]
    fn times_must_increase() {
        let error = Series::new(vec![0.0, 0.1, 0.1], vec![vec![0.0; 3]], 2).unwrap_err();
        assert_eq!(error, SignalError::TimesNotIncreasing { row: 2, time: 0.1, previous: 0.1 });
    }
}
