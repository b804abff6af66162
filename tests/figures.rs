//! Charts drawn as SVG (`osim_tune::figures`): every finite point lands where a single affine
//! map of its values puts it, y up; a gap breaks a line; a chart without data is an error;
//! table columns are drawn, and a missing column is named with its file.

mod common;

use std::path::Path;

use common::{pixel_map, svg_elements, svg_points};
use osim_tune::figures::{render, table_chart, Chart, FigureError, Mark, Series, TableSeries, Tone, SIZE};
use osim_tune::io::table::StorageTable;

fn chart(series: Vec<Series>) -> Chart {
    Chart { title: "test".into(), x_label: "x".into(), y_label: "y".into(), series }
}

fn circle_centres(svg: &str) -> Vec<(f64, f64)> {
    svg_elements(svg, "circle").iter().map(|c| (c["cx"].parse().unwrap(), c["cy"].parse().unwrap())).collect()
}

/// Pixels are whole numbers: a point is within 1.5 px of the affine map fitted to the extremes.
const PIXEL_TOLERANCE: f64 = 1.5;

#[test]
fn places_points_by_one_affine_map_with_y_up() {
    let points = vec![(-90.0, 132.5), (-75.0, 145.2), (-60.0, 160.4), (-45.0, 173.0), (-30.0, 160.5), (-52.5, -20.0)];
    let svg = render(&chart(vec![Series::new("", points.clone(), Mark::Circles, Tone::Measured)])).unwrap();
    let centres = circle_centres(&svg);
    assert_eq!(centres.len(), points.len(), "{svg}");
    let x_map = pixel_map(&points.iter().zip(&centres).map(|(p, c)| (p.0, c.0)).collect::<Vec<_>>());
    let y_map = pixel_map(&points.iter().zip(&centres).map(|(p, c)| (p.1, c.1)).collect::<Vec<_>>());
    for (point, centre) in points.iter().zip(&centres) {
        assert!((x_map(point.0) - centre.0).abs() <= PIXEL_TOLERANCE && (y_map(point.1) - centre.1).abs() <= PIXEL_TOLERANCE, "{point:?} at {centre:?}");
        assert!(centre.0 > 0.0 && centre.0 < SIZE.0 as f64 && centre.1 > 0.0 && centre.1 < SIZE.1 as f64, "{centre:?} outside the canvas");
    }
    assert!(y_map(1.0) < y_map(0.0), "y must grow upwards");
    assert!(x_map(1.0) > x_map(0.0), "x must grow rightwards");
}

#[test]
fn a_gap_breaks_a_line_and_a_legend_names_the_series() {
    let points = vec![(0.0, 0.0), (1.0, 1.0), (2.0, f64::NAN), (3.0, 2.0), (4.0, 1.0), (5.0, 3.0)];
    let svg = render(&chart(vec![Series::new("", points, Mark::Line, Tone::Fitted)])).unwrap();
    let lines: Vec<_> = svg_elements(&svg, "polyline").into_iter().filter(|l| l["stroke"] == "#1F77B4").collect();
    assert_eq!(lines.iter().map(|l| svg_points(l).len()).collect::<Vec<_>>(), vec![2, 3], "{svg}");
    let labelled = render(&chart(vec![Series::new("fitted model", vec![(0.0, 1.0), (1.0, 2.0)], Mark::Line, Tone::Fitted)])).unwrap();
    assert!(labelled.contains("fitted model") && !svg.contains("fitted model"));
}

#[test]
fn a_chart_without_a_finite_point_is_an_error() {
    let empty = chart(vec![Series::new("a", vec![(f64::NAN, 1.0), (2.0, f64::INFINITY)], Mark::Line, Tone::Palette(0))]);
    assert!(matches!(render(&empty), Err(FigureError::NoData { .. })));
    assert!(matches!(render(&chart(Vec::new())), Err(FigureError::NoData { .. })));
}

#[test]
fn draws_table_columns_and_names_a_missing_one_with_its_file() {
    let table = StorageTable::new("q", vec!["time".into(), "knee_angle_r".into(), "hip_flexion_r".into()], vec![0.0, 10.0, 5.0, 0.1, 20.0, 6.0, 0.2, 15.0, 7.0]).unwrap();
    let file = Path::new("trial_ik.mot");
    let tables = [TableSeries { file, table: &table }, TableSeries { file: Path::new("other.mot"), table: &table }];
    let columns = vec!["knee_angle_r".to_string()];
    let chart = table_chart(&tables[..1], &columns, None, "IK", "angle (°)").unwrap();
    assert_eq!(chart.series.len(), 1);
    assert_eq!(chart.series[0].points, vec![(0.0, 10.0), (0.1, 20.0), (0.2, 15.0)]);
    let against_hip = table_chart(&tables, &columns, Some("hip_flexion_r"), "IK", "angle (°)").unwrap();
    assert_eq!(against_hip.series.iter().map(|s| s.label.as_str()).collect::<Vec<_>>(), ["trial_ik.mot: knee_angle_r", "other.mot: knee_angle_r"]);
    assert_eq!(against_hip.series[1].points[2], (7.0, 15.0));
    assert_ne!(against_hip.series[0].mark, against_hip.series[1].mark, "tables must be told apart");
    let missing = table_chart(&tables, &["ankle_angle_r".to_string()], None, "IK", "").unwrap_err().to_string();
    assert!(missing.contains("trial_ik.mot") && missing.contains("ankle_angle_r") && missing.contains("knee_angle_r"), "{missing}");
}

#[test]
fn plot_command_draws_a_column_of_each_table_and_refuses_what_it_cannot_draw() {
    let dir = tempfile::tempdir().unwrap();
    let (ik, coordinates) = (common::fixture("golden/ik/coordinate_file/ik.mot"), common::fixture("golden/ik/coordinate_file/coordinates.mot"));
    let output = dir.path().join("figures/knee.svg");
    let s = |p: &Path| p.to_str().unwrap().to_string();
    let (code, _, stderr) = common::osim_tune(&["plot", &s(&ik), &s(&coordinates), "--columns", "knee_angle_r", "-o", &s(&output)]);
    assert_eq!(code, 0, "{stderr}");
    let svg = std::fs::read_to_string(&output).unwrap();
    // The first table's column is one solid polyline through every row.
    let rows = StorageTable::read(&ik).unwrap().n_rows();
    let solid = svg_elements(&svg, "polyline").into_iter().filter(|l| l["stroke-width"] == "2").map(|l| svg_points(&l).len()).max().unwrap();
    assert_eq!(solid, rows);
    assert!(svg.contains("ik.mot: knee_angle_r") && svg.contains("coordinates.mot: knee_angle_r"));
    for (arguments, expected) in [
        (vec!["--columns", "knee_angle_r", "-o", "knee.png"], "expected a .svg file name"),
        (vec!["--columns", "knee_angle_x", "-o", "knee2.svg"], "no column \"knee_angle_x\""),
        (vec!["--columns", "knee_angle_r", "--x", "nothing", "-o", "knee3.svg"], "no column \"nothing\""),
    ] {
        let output = dir.path().join(arguments.last().unwrap());
        let mut all = vec!["plot".to_string(), s(&ik)];
        all.extend(arguments[..arguments.len() - 1].iter().map(|a| a.to_string()));
        all.push(s(&output));
        let all: Vec<&str> = all.iter().map(String::as_str).collect();
        let (code, _, stderr) = common::osim_tune(&all);
        assert_eq!(code, 2, "{stderr}");
        assert!(stderr.contains(expected) && !output.exists(), "{stderr}");
    }
}
