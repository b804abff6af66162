//! OpenSim tables: the shipped fixtures read with the right shapes and values, round-trip
//! bit-exactly, convert units explicitly, and arbitrary input never panics the parsers.

use std::path::{Path, PathBuf};

use osim_tune::io::table::{LengthUnit, MarkerTable, StorageTable, TableError, TrcHeader};
use proptest::prelude::*;

fn fixture(relative: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures").join(relative)
}

/// Every file under `fixtures/` whose extension is one of `extensions`.
fn fixtures_with(extensions: &[&str]) -> Vec<PathBuf> {
    let mut found = Vec::new();
    let mut pending = vec![fixture("")];
    while let Some(directory) = pending.pop() {
        for entry in std::fs::read_dir(&directory).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                pending.push(path);
            } else if path.extension().is_some_and(|ext| extensions.iter().any(|wanted| ext == *wanted)) {
                found.push(path);
            }
        }
    }
    found.sort();
    found
}

fn read_storage(relative: &str) -> StorageTable {
    StorageTable::read(&fixture(relative)).unwrap_or_else(|error| panic!("{error}"))
}

fn read_markers(relative: &str) -> MarkerTable {
    MarkerTable::read(&fixture(relative)).unwrap_or_else(|error| panic!("{error}"))
}

fn bits(values: &[f64]) -> Vec<u64> {
    values.iter().map(|value| value.to_bits()).collect()
}

fn position_bits(table: &MarkerTable) -> Vec<Option<[u64; 3]>> {
    table.positions().iter().map(|position| position.map(|xyz| xyz.map(f64::to_bits))).collect()
}

fn assert_same_storage(back: &StorageTable, original: &StorageTable, what: &str) {
    assert_eq!(back.name(), original.name(), "{what}: name");
    assert_eq!(back.in_degrees(), original.in_degrees(), "{what}: inDegrees");
    assert_eq!(back.metadata(), original.metadata(), "{what}: metadata");
    assert_eq!(back.comments(), original.comments(), "{what}: comments");
    assert_eq!(back.labels(), original.labels(), "{what}: labels");
    assert!(bits(back.values()) == bits(original.values()), "{what}: values differ");
}

fn assert_same_markers(back: &MarkerTable, original: &MarkerTable, what: &str) {
    let (header, original_header) = (back.header(), original.header());
    assert_eq!(header.file_name, original_header.file_name, "{what}: file name");
    assert_eq!(header.data_rate.to_bits(), original_header.data_rate.to_bits(), "{what}: DataRate");
    assert_eq!(header.camera_rate.to_bits(), original_header.camera_rate.to_bits(), "{what}: CameraRate");
    assert_eq!(header.units, original_header.units, "{what}: Units");
    assert_eq!(header.orig_data_rate.map(f64::to_bits), original_header.orig_data_rate.map(f64::to_bits));
    assert_eq!(header.orig_data_start_frame, original_header.orig_data_start_frame, "{what}");
    assert_eq!(header.orig_num_frames, original_header.orig_num_frames, "{what}");
    assert_eq!(header.extra, original_header.extra, "{what}: extra fields");
    assert_eq!(back.marker_names(), original.marker_names(), "{what}: marker names");
    assert_eq!(back.frame_numbers(), original.frame_numbers(), "{what}: frame numbers");
    assert!(bits(back.times()) == bits(original.times()), "{what}: times differ");
    assert!(position_bits(back) == position_bits(original), "{what}: positions differ");
}

#[test]
fn static_trial_markers() {
    let table = read_markers("subject01/subject01_static.trc");
    assert_eq!((table.n_frames(), table.n_markers()), (300, 49));
    assert_eq!(table.units(), LengthUnit::Millimeters);
    assert_eq!(table.rate(), 60.0);
    assert_eq!(table.header().file_name, "subject01_static.trc");
    assert_eq!(table.header().orig_num_frames, Some(300));
    assert_eq!(table.marker_names().last().map(String::as_str), Some("Top.Head"));
    assert_eq!((table.frame_numbers()[299], table.times()[299]), (300, 4.983));
    let r_asis = table.marker_index("R.ASIS").unwrap();
    // Frame 1 of the file: `608.664310  1072.713130  157.442150` mm.
    assert_eq!(table.position(0, r_asis), Some([608.66431, 1072.71313, 157.44215]));
    assert_eq!(table.position(299, r_asis), Some([602.00366, 1073.36719, 157.64821]));

    let meters = table.in_meters();
    assert_eq!(meters.units(), LengthUnit::Meters);
    let [x, y, z] = meters.position(0, r_asis).unwrap();
    approx::assert_relative_eq!(x, 0.60866431, max_relative = 1e-15);
    approx::assert_relative_eq!(y, 1.07271313, max_relative = 1e-15);
    approx::assert_relative_eq!(z, 0.15744215, max_relative = 1e-15);
    assert!(meters.to_text().lines().nth(2).unwrap().contains("\tm\t"));
}

#[test]
fn walking_trial_markers() {
    let table = read_markers("subject01/subject01_walk1.trc");
    assert_eq!((table.n_frames(), table.n_markers()), (151, 41));
    assert_eq!(&table.marker_names()[..3], ["R.ASIS", "L.ASIS", "V.Sacral"]);
    assert_eq!(table.times()[150], 2.5);
    assert!(table.positions().iter().all(Option::is_some));
}

#[test]
fn ground_reaction_forces() {
    let table = read_storage("subject01/subject01_walk1_grf.mot");
    assert_eq!((table.n_rows(), table.n_columns()), (1501, 19));
    assert_eq!(table.in_degrees(), Some(true));
    assert_eq!(table.name(), "subject01_walk1_grf.mot");
    assert_eq!(table.labels()[0], "time");
    assert_eq!(table.column("ground_force_vy").unwrap()[0], 745.4661142);
    let times = table.times();
    assert_eq!((times[0], times[1], times[1500]), (0.0, 0.0017, 2.5));
}

#[test]
fn legacy_simm_inverse_kinematics() {
    let table = read_storage("subject01/OutputReference/subject01_walk1_ik.mot");
    assert_eq!((table.n_rows(), table.n_columns()), (211, 165));
    assert_eq!(table.name(), "first trial");
    // No inDegrees and no version: a SIMM motion, in degrees as OpenSim's Storage reads it.
    assert_eq!(table.in_degrees(), Some(true));
    assert!(table.comments().iter().any(|line| line == "# SIMM Motion File Header:"));
    assert_eq!(table.column("pelvis_tx").unwrap()[0], 0.5897903832585103);
    // Row 1 of the file: `-19.88552911045664800000`.
    assert_eq!(table.column("knee_angle_r").unwrap()[0], "-19.885529110456648".parse::<f64>().unwrap());
    assert_eq!(table.times()[210], 4.0);
    // Both feet's ground-force columns share labels: readable, but not looked up by label.
    assert!(table.duplicate_labels().contains(&"ground_force_vx"));
    assert_eq!(table.column_indices("ground_force_vx").len(), 2);
    assert_eq!(table.column("ground_force_vx"), None);
}

#[test]
fn inverse_dynamics_output() {
    let table = read_storage("subject01/OutputReference/InverseDynamicsOutput.sto");
    assert_eq!((table.n_rows(), table.n_columns()), (73, 24));
    assert_eq!(table.name(), "Inverse Dynamics");
    assert_eq!(table.in_degrees(), Some(false));
    assert_eq!(table.times()[0], 0.39999934);
    assert_eq!(table.column("knee_angle_r_moment").unwrap()[0], 21.14172236);
}

#[test]
fn every_storage_fixture_round_trips_bit_exactly() {
    let paths = fixtures_with(&["sto", "mot"]);
    assert!(paths.len() >= 3, "expected the subject01 .sto/.mot fixtures, found {paths:?}");
    for path in paths {
        let original = StorageTable::read(&path).unwrap_or_else(|error| panic!("{error}"));
        let text = original.to_text();
        let back = StorageTable::parse(&text, &path).unwrap_or_else(|error| panic!("{error}"));
        assert_same_storage(&back, &original, &path.display().to_string());
        assert_eq!(back.to_text(), text, "{}: second write differs", path.display());
    }
}

#[test]
fn every_marker_fixture_round_trips_bit_exactly() {
    let paths = fixtures_with(&["trc"]);
    assert!(paths.len() >= 2, "expected the subject01 .trc fixtures, found {paths:?}");
    for path in paths {
        let original = MarkerTable::read(&path).unwrap_or_else(|error| panic!("{error}"));
        let text = original.to_text();
        let back = MarkerTable::parse(&text, &path).unwrap_or_else(|error| panic!("{error}"));
        assert_same_markers(&back, &original, &path.display().to_string());
        assert_eq!(back.to_text(), text, "{}: second write differs", path.display());
    }
}

#[test]
fn degrees_to_radians_on_rotational_columns_and_back() {
    let original = read_storage("subject01/OutputReference/subject01_walk1_ik.mot").with_in_degrees(true);
    let rotational =
        |label: &str| !(label.ends_with("_tx") || label.ends_with("_ty") || label.ends_with("_tz"));
    let radians = original.to_radians(rotational).unwrap();
    assert_eq!(radians.in_degrees(), Some(false));
    let knee = radians.column("knee_angle_r").unwrap()[0];
    let knee_degrees = original.column("knee_angle_r").unwrap()[0];
    assert!(knee_degrees < -19.0);
    approx::assert_relative_eq!(knee, knee_degrees * std::f64::consts::PI / 180.0, max_relative = 1e-15);
    assert_eq!(bits(&radians.column("pelvis_tx").unwrap()), bits(&original.column("pelvis_tx").unwrap()));
    assert_eq!(bits(&radians.times()), bits(&original.times()));

    let degrees = radians.to_degrees(rotational).unwrap();
    assert_eq!(degrees.in_degrees(), Some(true));
    for (back, value) in degrees.values().iter().zip(original.values()) {
        assert!((back - value).abs() <= 1e-12 * value.abs(), "{back} != {value}");
    }
}

#[test]
fn conversion_of_an_undeclared_table_is_refused() {
    // The SIMM motion's text in a `.sto`: nothing declares the unit (OpenSim: radians).
    let text = std::fs::read_to_string(fixture("subject01/OutputReference/subject01_walk1_ik.mot")).unwrap();
    let legacy = StorageTable::parse(&text, Path::new("subject01_walk1_ik.sto")).unwrap();
    assert_eq!(legacy.in_degrees(), None);
    let error = legacy.to_radians(|_| true).unwrap_err();
    assert!(matches!(error, TableError::UnknownAngleUnit { .. }), "{error}");
}

#[test]
fn read_errors_name_the_file() {
    let missing = fixture("subject01/no_such_table.sto");
    let message = StorageTable::read(&missing).unwrap_err().to_string();
    assert!(message.starts_with(&missing.display().to_string()), "{message}");
    let not_text = tempfile::NamedTempFile::new().unwrap();
    std::fs::write(not_text.path(), b"name\nendheader\ntime\n\x00\xfe\n").unwrap();
    let message = StorageTable::read(not_text.path()).unwrap_err().to_string();
    assert_eq!(message, format!("{}:4: binary data (a NUL byte); expected a text table", not_text.path().display()));
    let message = MarkerTable::read(not_text.path()).unwrap_err().to_string();
    assert!(message.starts_with(&format!("{}:4:", not_text.path().display())), "{message}");
}

/// Finite doubles of every class: normal, subnormal, zero, both signs, any bits.
fn finite_value() -> impl Strategy<Value = f64> {
    use proptest::num::f64 as float;
    prop_oneof![
        float::POSITIVE | float::NEGATIVE | float::NORMAL | float::SUBNORMAL | float::ZERO,
        any::<u64>().prop_map(f64::from_bits).prop_filter("finite", |value| value.is_finite()),
        Just(-0.0),
        Just(f64::MAX),
        Just(f64::MIN_POSITIVE),
        Just(5e-324),
    ]
}

/// Column labels after `time`: unique words, some with inner spaces.
fn data_labels() -> impl Strategy<Value = Vec<String>> {
    proptest::collection::btree_set("[A-Za-z_][A-Za-z0-9_./]{0,8}( [A-Za-z0-9_]{1,4})?", 0..6)
        .prop_map(|labels| labels.into_iter().filter(|label| label != "time").collect())
}

/// Header text: metadata pairs and comment lines of printable ASCII. Pairs or comments that
/// the table refuses (layout keys, comments that would read as fields) are left out.
fn header_text() -> impl Strategy<Value = (Vec<(String, String)>, Vec<String>)> {
    (
        proptest::collection::vec(("[A-Za-z][A-Za-z0-9_]{0,6}", "[ -~]{0,10}"), 0..3),
        proptest::collection::vec("[ -~]{0,20}", 0..3),
    )
}

fn random_storage() -> impl Strategy<Value = StorageTable> {
    (data_labels(), 0usize..8, proptest::option::of(any::<bool>()), header_text()).prop_flat_map(
        |(labels, rows, in_degrees, (metadata, comments))| {
            let width = labels.len() + 1;
            proptest::collection::vec(finite_value(), rows * width).prop_map(move |values| {
                let labels = std::iter::once("time".to_owned()).chain(labels.iter().cloned()).collect();
                let mut table = StorageTable::new("random table", labels, values).unwrap();
                if let Some(in_degrees) = in_degrees {
                    table = table.with_in_degrees(in_degrees);
                }
                for (key, value) in &metadata {
                    table = table.clone().with_metadata(key, value).unwrap_or(table);
                }
                for comment in &comments {
                    table = table.clone().with_comment(comment).unwrap_or(table);
                }
                table
            })
        },
    )
}

fn random_markers() -> impl Strategy<Value = MarkerTable> {
    let names = proptest::collection::btree_set("[A-Za-z][A-Za-z0-9_.]{0,6}( [A-Za-z]{1,3})?", 0..5);
    (names, 0usize..6, finite_value()).prop_flat_map(|(names, frames, rate)| {
        let position = proptest::option::of(proptest::array::uniform3(finite_value()));
        (
            proptest::collection::vec(finite_value(), frames),
            proptest::collection::vec(position, frames * names.len()),
            prop_oneof![
                Just(LengthUnit::Millimeters),
                Just(LengthUnit::Centimeters),
                Just(LengthUnit::Meters)
            ],
        )
            .prop_map(move |(times, positions, units)| {
                let names = names.iter().cloned().collect();
                MarkerTable::new(TrcHeader::new(rate, units), names, times, positions).unwrap()
            })
    })
}

/// Text shaped like a table header and rows, so that parsing gets past the first checks.
fn table_like_text() -> impl Strategy<Value = String> {
    let line = prop_oneof![
        Just("endheader".to_owned()),
        "(nRows|nColumns|inDegrees|datarows|datacolumns)[= ][0-9a-z]{0,3}",
        "PathFileType\t4\t\\(X/Y/Z\\)\tx.trc",
        "DataRate\tCameraRate\tNumFrames\tNumMarkers\tUnits",
        "[0-9]{1,3}\t[0-9]{1,3}\t[0-9]\t[0-9]\t(mm|m|cm|in)",
        "Frame#\tTime(\t[A-Z]{1,2}\t\t){0,2}",
        "\t\t(X[0-9]\tY[0-9]\tZ[0-9]\t){0,2}",
        "(time|[a-z]{1,3})([\t ][a-z]{1,3}){0,3}",
        "[0-9.eE+\\-naif\t ]{0,20}",
        "[\\PC\t]{0,12}",
    ];
    proptest::collection::vec(line, 0..12).prop_map(|lines| lines.join("\n"))
}

proptest! {
    #[test]
    fn random_storage_tables_round_trip_bit_exactly(table in random_storage()) {
        let back = StorageTable::parse(&table.to_text(), Path::new("random.sto")).unwrap();
        assert_same_storage(&back, &table, "random table");
    }

    #[test]
    fn random_marker_tables_round_trip_bit_exactly(table in random_markers()) {
        let back = MarkerTable::parse(&table.to_text(), Path::new("random.trc")).unwrap();
        assert_same_markers(&back, &table, "random markers");
    }

    #[test]
    fn arbitrary_text_never_panics(text in any::<String>()) {
        let _ = StorageTable::parse(&text, Path::new("fuzz.sto"));
        let _ = MarkerTable::parse(&text, Path::new("fuzz.trc"));
    }

    #[test]
    fn table_like_text_never_panics(text in table_like_text()) {
        let _ = StorageTable::parse(&text, Path::new("fuzz.sto"));
        let _ = MarkerTable::parse(&text, Path::new("fuzz.trc"));
    }

    #[test]
    fn arbitrary_bytes_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..256)) {
        let _ = StorageTable::from_bytes(&bytes, Path::new("fuzz.sto"));
        let _ = MarkerTable::from_bytes(&bytes, Path::new("fuzz.trc"));
    }
}
