//! `osim-tune dynamometer MODEL COORDINATES --load-cell LOADS.xml [--crank BODY] [--knee COORDINATE] [--dynamometer-moment COLUMN [--dynamometer-sign -1]] [--time START END] [--lowpass HZ] [--perturb-…] [--json] [--report R.json] -o OUT.sto`

use std::path::{Path, PathBuf};

use crate::analysis::{dynamometer_analysis, Agreements, DynamometerModel, DynamometerSettings, DynamometerSummary, ExternalLoads, MeasuredMoment, Perturbations, SplinedMotion};
use crate::cli::{check_time_and_cutoff, create_output_folders, Failure, Outcome};
use crate::io::atomic::{ensure_not_an_input, write_all_atomically};
use crate::io::osim::OsimDocument;
use crate::io::table::StorageTable;
use crate::mechanics::Multibody;
use crate::model::ModelSpec;

/// What the command line asks for besides the model and the coordinates.
pub struct Request {
    pub load_cell: PathBuf,
    pub crank: String,
    pub knee: String,
    pub dynamometer_moment: Option<String>,
    /// ±1.
    pub dynamometer_sign: f64,
    pub time: Option<[f64; 2]>,
    pub lowpass: Option<f64>,
    pub perturbations: Perturbations,
    pub json: bool,
    pub report: Option<PathBuf>,
    pub output: PathBuf,
}

pub fn run(model: &Path, coordinates: &Path, request: &Request) -> Result<Outcome, Failure> {
    check_time_and_cutoff(request.time, request.lowpass)?;
    check_perturbations(&request.perturbations)?;
    let multibody = Multibody::new(&ModelSpec::read(&OsimDocument::read(model)?)?)?;
    let dynamometer = DynamometerModel::new(&multibody, &request.crank, &request.knee)?;
    let (loads, data_file) = ExternalLoads::read(&request.load_cell, &multibody)?;
    crate::cli::warn_about(&loads.warnings);
    dynamometer.check_load_cell(&multibody, &loads, &request.load_cell)?;
    let inputs = [model, coordinates, request.load_cell.as_path(), data_file.as_path()];
    for output in std::iter::once(&request.output).chain(&request.report) {
        ensure_not_an_input(output, &inputs)?;
    }
    if let Some(report) = &request.report {
        ensure_not_an_input(report, &[request.output.as_path()]).map_err(|_| format!("{}: --report and -o name the same file", report.display()))?;
    }
    let measured = match &request.dynamometer_moment {
        Some(column) => Some(MeasuredMoment::new(&StorageTable::read(&data_file)?, &data_file, column, request.dynamometer_sign)?),
        None => None,
    };
    let motion = SplinedMotion::new(&multibody, &StorageTable::read(coordinates)?, coordinates, request.lowpass)?;
    let settings = DynamometerSettings { time_range: request.time.unwrap_or([f64::NEG_INFINITY, f64::INFINITY]), perturbations: request.perturbations };
    let result = dynamometer_analysis(&multibody, &dynamometer, &motion, &loads, measured.as_ref(), &settings)?;
    let table = result.table(&multibody, &dynamometer)?.to_text();
    let summary = result.summary();
    let json = serde_json::to_string_pretty(&summary)?;
    let outputs: Vec<(&Path, &[u8])> = std::iter::once((request.output.as_path(), table.as_bytes())).chain(request.report.as_deref().map(|r| (r, json.as_bytes()))).collect();
    create_output_folders(outputs.iter().map(|(file, _)| *file))?;
    write_all_atomically(&outputs, &inputs)?;
    if request.json {
        println!("{json}");
    } else {
        print_summary(&summary, &request.knee, measured.as_ref(), &result.defaulted, &request.output);
    }
    Ok(Outcome::Success)
}

/// Sizes must be finite and ≥ 0.
fn check_perturbations(p: &Perturbations) -> Result<(), Failure> {
    for (flag, value) in [("--perturb-axis-angle", p.axis_angle), ("--perturb-axis-offset", p.axis_offset), ("--perturb-mass", p.mass), ("--perturb-mass-center", p.mass_center)] {
        if !(value.is_finite() && value >= 0.0) {
            return Err(format!("{flag} {value}: expected a size ≥ 0").into());
        }
    }
    Ok(())
}

fn print_summary(summary: &DynamometerSummary, knee: &str, measured: Option<&MeasuredMoment>, defaulted: &[String], output: &Path) {
    let [first, last] = summary.time_range;
    println!("{} frames ({first:.4}–{last:.4} s) → {}", summary.frames, output.display());
    if !defaulted.is_empty() {
        println!("held at their default value (not in the coordinates): {}", defaulted.join(", "));
    }
    let (offset, angle) = (&summary.axis_offset, &summary.axis_angle);
    println!("knee axis from the dynamometer's: {:.1} ± {:.1} mm (largest {:.1} mm), {:.2} ± {:.2}° apart (largest {:.2}°)", offset.mean * 1e3, offset.sd * 1e3, offset.max * 1e3, angle.mean, angle.sd, angle.max);
    println!(
        "pad force to the crank's normal: {:.1} ± {:.1}° (largest {:.1}°); within 15° in {:.1} % of the frames",
        summary.pad_force_angle.mean,
        summary.pad_force_angle.sd,
        summary.pad_force_angle.max,
        summary.perpendicular_share * 100.0
    );
    if let (Some(dynamometer), Some(herzog), Some(measured)) = (&summary.dynamometer, &summary.herzog, measured) {
        println!("agreement with M3D ({knee}'s generalized force), N·m — Bland–Altman, 95 % limits:");
        print_agreements(&format!("Mdyn ({})", measured.column), dynamometer);
        print_agreements("M2D (Herzog)", herzog);
    }
    println!("sensitivity of M3D (largest / RMS change over the frames, N·m):");
    for row in &summary.sensitivity {
        println!("  {:<44} ±{:<10} {:>8.3} {:>8.3}", row.parameter, row.size, row.max_change, row.rms_change);
    }
}

fn print_agreements(what: &str, agreements: &Agreements) {
    for (sign, agreement) in [("M3D > 0", &agreements.positive), ("M3D < 0", &agreements.negative)] {
        if let Some(a) = agreement {
            println!(
                "  {what:<22} {sign}: {} frames, peak |M3D| {:.2}; {what} − M3D mean {:+.2} (sd {:.2}, limits {:+.2} … {:+.2}), largest {:.2} ({:.1} % of the peak) at {:.4} s",
                a.frames,
                a.peak,
                a.mean,
                a.sd,
                a.limits[0],
                a.limits[1],
                a.largest,
                100.0 * a.largest / a.peak,
                a.largest_time
            );
        }
    }
}
