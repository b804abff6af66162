//! `cargo xtask fuzz-smoke [SECONDS]`: feeds mutated copies of the fixtures (bit flips, byte
//! insertions and deletions, truncation, splices of other inputs) to every parser — documents
//! into the model view (2.x/3.x ones also converted to 4.x and read again), force sets and every
//! tool setup (Scale, IK, ID, Analyze, ExternalLoads)
//! — for a bounded time and reports any panic. Seeded, so a failing run can be repeated.

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::Path;
use std::process::ExitCode;
use std::time::{Duration, Instant};

use osim_tune::io::osim::OsimDocument;
use osim_tune::io::table::{MarkerTable, StorageTable};
use osim_tune::model::{read_force_set, upgrade, ModelSpec};
use osim_tune::setup::{AnalyzeSetup, ExternalLoadsSetup, IdSetup, IkSetup, ScaleSetup};
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};

use crate::{files_with, root};

/// A parser under test: takes bytes, must return (Ok or Err) without panicking.
type Parser = fn(&[u8]);

fn parse_osim(bytes: &[u8]) {
    let text = String::from_utf8_lossy(bytes).into_owned();
    if let Ok(document) = OsimDocument::parse(text, Path::new("fuzz.osim")) {
        let _ = ModelSpec::read(&document);
        if let Ok(converted) = upgrade(&document) {
            let _ = ModelSpec::read(&converted);
        }
        let _ = read_force_set(&document);
        let _ = (ScaleSetup::from_document(&document), IkSetup::from_document(&document), IdSetup::from_document(&document));
        let _ = (AnalyzeSetup::from_document(&document), ExternalLoadsSetup::from_document(&document));
        let _ = document.xml.serialize();
    }
}

fn parse_storage(bytes: &[u8]) {
    if let Ok(table) = StorageTable::from_bytes(bytes, Path::new("fuzz.sto")) {
        let _ = table.to_text();
    }
}

fn parse_markers(bytes: &[u8]) {
    if let Ok(table) = MarkerTable::from_bytes(bytes, Path::new("fuzz.trc")) {
        let _ = table.to_text();
    }
}

pub fn run(seconds: f64) -> ExitCode {
    let seed = 20261121;
    let mut rng = StdRng::seed_from_u64(seed);
    let corpora: [(&str, Parser, Vec<Vec<u8>>); 3] = [
        ("osim/xml", parse_osim, corpus(&["osim", "xml"], 120_000)),
        ("sto/mot", parse_storage, corpus(&["sto", "mot"], 60_000)),
        ("trc", parse_markers, corpus(&["trc"], 60_000)),
    ];
    std::panic::set_hook(Box::new(|_| {}));
    let deadline = Instant::now() + Duration::from_secs_f64(seconds);
    let (mut runs, mut panics) = ([0usize; 3], 0usize);
    while Instant::now() < deadline {
        for (index, (name, parser, inputs)) in corpora.iter().enumerate() {
            let input = mutate(&inputs[rng.random_range(0..inputs.len())], &inputs[rng.random_range(0..inputs.len())], &mut rng);
            if catch_unwind(AssertUnwindSafe(|| parser(&input))).is_err() {
                panics += 1;
                let file = std::env::temp_dir().join(format!("osim-tune-fuzz-{name}-{panics}.bin").replace('/', "_"));
                let _ = std::fs::write(&file, &input);
                eprintln!("panic in the {name} parser; input saved to {}", file.display());
            }
            runs[index] += 1;
        }
    }
    let _ = std::panic::take_hook();
    println!(
        "fuzz-smoke (seed {seed}, {seconds} s): osim/xml {} inputs, sto/mot {} inputs, trc {} inputs, {panics} panics",
        runs[0], runs[1], runs[2]
    );
    if panics == 0 { ExitCode::SUCCESS } else { ExitCode::FAILURE }
}

/// Fixture files with these extensions, each cut to at most `limit` bytes to keep runs fast.
fn corpus(extensions: &[&str], limit: usize) -> Vec<Vec<u8>> {
    files_with(&root().join("fixtures"), extensions)
        .into_iter()
        .filter_map(|p| std::fs::read(p).ok())
        .map(|mut bytes| {
            bytes.truncate(limit);
            bytes
        })
        .collect()
}

/// A few random edits of `input`, sometimes spliced with `other`.
fn mutate(input: &[u8], other: &[u8], rng: &mut StdRng) -> Vec<u8> {
    let mut bytes = input.to_vec();
    for _ in 0..rng.random_range(1..8) {
        if bytes.is_empty() {
            break;
        }
        let at = rng.random_range(0..bytes.len());
        match rng.random_range(0..6) {
            0 => bytes[at] ^= 1 << rng.random_range(0..8),
            1 => bytes.insert(at, *b"<>/=\"\t\n 0.-e&;#x".get(rng.random_range(0..16)).unwrap()),
            2 => {
                let end = (at + rng.random_range(1..64)).min(bytes.len());
                bytes.drain(at..end);
            }
            3 => bytes.truncate(at),
            4 if !other.is_empty() => {
                let from = rng.random_range(0..other.len());
                let end = (from + rng.random_range(1..256)).min(other.len());
                bytes.splice(at..at, other[from..end].iter().copied());
            }
            _ => bytes[at] = rng.random(),
        }
    }
    bytes
}
