//! Project tasks: `cargo xtask validate` (conformance table against OpenSim goldens and
//! round-trip checks; exits non-zero on any failure), `cargo xtask bench` (speed beside
//! OpenSim), `cargo xtask fuzz-smoke [SECONDS]` (mutated inputs into every parser for a bounded
//! time; exits non-zero on a panic) and `cargo xtask diagnose-study DIR` (the diagnosis'
//! verdicts on a blind batch of hidden changes; exits non-zero on a wrong name).

mod bench;
mod bench_analyze;
mod bench_scale;
mod bench_forward;
mod bench_functional;
mod bench_ik;
mod bench_reaction;
mod bench_cmc;
mod bench_rra;
mod dynamics;
mod functional;
mod functional_generated;
mod fuzz;
mod geometry;
mod ik;
mod kalman_ik;
mod knee_axis;
mod knee_swap;
mod muscle;
mod cmc;
mod rra;
mod scale;
mod validate;

use std::process::ExitCode;

fn main() -> ExitCode {
    let arguments: Vec<String> = std::env::args().skip(1).collect();
    match arguments.first().map(String::as_str) {
        Some("validate") => validate::run(),
        Some("bench") => bench::run(),
        Some("diagnose-study") => match arguments.get(1) {
            Some(folder) => functional::diagnose_study(std::path::Path::new(folder)),
            None => usage(),
        },
        Some("fuzz-smoke") => {
            let seconds = arguments.get(1).and_then(|s| s.parse().ok()).unwrap_or(60.0);
            fuzz::run(seconds)
        }
        _ => usage(),
    }
}

fn usage() -> ExitCode {
    eprintln!("usage: cargo xtask validate | cargo xtask bench | cargo xtask fuzz-smoke [SECONDS (default 60)] | cargo xtask diagnose-study DIR");
    ExitCode::from(2)
}

/// The repository root (the parent of `xtask/`).
pub fn root() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).parent().unwrap().to_path_buf()
}

/// Files below `directory` (recursively) whose extension is one of `extensions`, sorted.
pub fn files_with(directory: &std::path::Path, extensions: &[&str]) -> Vec<std::path::PathBuf> {
    let mut found = Vec::new();
    let mut pending = vec![directory.to_path_buf()];
    while let Some(dir) = pending.pop() {
        for entry in std::fs::read_dir(&dir).into_iter().flatten().flatten() {
            let path = entry.path();
            if path.is_dir() {
                pending.push(path);
            } else if path.extension().and_then(|e| e.to_str()).is_some_and(|e| extensions.contains(&e)) {
                found.push(path);
            }
        }
    }
    found.sort();
    found
}
