//! A line chart described by its data — title, axis labels, series of (x, y) points — and drawn
//! as an SVG document with `plotters`. Axis ranges cover every finite point with a 5 % margin;
//! a non-finite point breaks a line (a gap in a table column is not bridged).

use plotters::chart::SeriesAnno;
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;

use super::FigureError;

/// Width and height of a drawn chart, px.
pub const SIZE: (u32, u32) = (800, 560);
/// Marker radius (half side for squares and triangles), px.
const MARKER_SIZE: i32 = 4;
/// Radius of the small dots of a dense point cloud, px.
const DOT_SIZE: i32 = 2;

/// A chart: its series are drawn in order, each in the legend under its label unless the label
/// is empty.
#[derive(Debug, Clone, PartialEq)]
pub struct Chart {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub series: Vec<Series>,
}

/// One series of points and how it is drawn.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    pub label: String,
    pub points: Vec<(f64, f64)>,
    pub mark: Mark,
    pub tone: Tone,
}

/// How a series is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mark {
    /// A solid line through the points in their order.
    Line,
    /// A dashed line through the points in their order.
    Dashed,
    /// A filled circle at each point (radius 4 px).
    Circles,
    /// A small filled dot at each point (radius 2 px), for point clouds.
    Dots,
    /// An open square at each point.
    Squares,
    /// A filled triangle at each point.
    Triangles,
}

/// The colour of a series: the roles of a fit's figures, or the n-th colour of a palette for
/// series of equal standing (table columns).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Tone {
    Measured,
    Initial,
    Fitted,
    /// A diagnosed cause's model.
    Cause,
    Background,
    Palette(usize),
}

impl Tone {
    fn color(self) -> RGBColor {
        match self {
            Tone::Measured => BLACK,
            Tone::Initial => RGBColor(128, 128, 128),
            Tone::Fitted => RGBColor(31, 119, 180),
            Tone::Cause => RGBColor(255, 127, 14),
            Tone::Background => RGBColor(190, 205, 225),
            Tone::Palette(n) => {
                let color = Palette99::pick(n).to_rgba();
                RGBColor(color.0, color.1, color.2)
            }
        }
    }
}

impl Series {
    pub fn new(label: impl Into<String>, points: Vec<(f64, f64)>, mark: Mark, tone: Tone) -> Series {
        Series { label: label.into(), points, mark, tone }
    }

    fn finite_points(&self) -> impl Iterator<Item = (f64, f64)> + '_ {
        self.points.iter().copied().filter(|(x, y)| x.is_finite() && y.is_finite())
    }

    /// The runs of consecutive finite points, which a line joins.
    fn segments(&self) -> Vec<Vec<(f64, f64)>> {
        self.points
            .split(|(x, y)| !(x.is_finite() && y.is_finite()))
            .filter(|segment| !segment.is_empty())
            .map(<[(f64, f64)]>::to_vec)
            .collect()
    }
}

/// The chart as an SVG document; [`FigureError::NoData`] when no series has a finite point.
pub fn render(chart: &Chart) -> Result<String, FigureError> {
    let points = || chart.series.iter().flat_map(Series::finite_points);
    let x_range = padded_range(points().map(|p| p.0)).ok_or_else(|| FigureError::NoData { chart: chart.title.clone() })?;
    let y_range = padded_range(points().map(|p| p.1)).ok_or_else(|| FigureError::NoData { chart: chart.title.clone() })?;
    let y_range = with_legend_headroom(y_range, chart.series.iter().filter(|s| !s.label.is_empty()).count());
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, SIZE).into_drawing_area();
        draw(&root, chart, x_range, y_range).map_err(|error| FigureError::Draw { chart: chart.title.clone(), reason: error.to_string() })?;
    }
    Ok(svg)
}

type DrawError = DrawingAreaErrorKind<std::io::Error>;

fn draw(root: &DrawingArea<SVGBackend, Shift>, chart: &Chart, x_range: (f64, f64), y_range: (f64, f64)) -> Result<(), DrawError> {
    root.fill(&WHITE)?;
    let mut context = ChartBuilder::on(root)
        .caption(&chart.title, ("sans-serif", 20))
        .margin(12)
        .x_label_area_size(45)
        .y_label_area_size(65)
        .build_cartesian_2d(x_range.0..x_range.1, y_range.0..y_range.1)?;
    context.configure_mesh().x_desc(&chart.x_label).y_desc(&chart.y_label).light_line_style(WHITE).draw()?;
    for series in &chart.series {
        draw_series(&mut context, series)?;
    }
    if chart.series.iter().any(|s| !s.label.is_empty()) {
        context.configure_series_labels().background_style(WHITE.mix(0.85)).border_style(BLACK).position(SeriesLabelPosition::UpperRight).draw()?;
    }
    root.present()
}

type Context<'a, 'b> = ChartContext<'a, SVGBackend<'b>, Cartesian2d<RangedCoordf64, RangedCoordf64>>;
type Annotation<'c, 'a, 'b> = &'c mut SeriesAnno<'a, SVGBackend<'b>>;

/// Draws a series; its legend entry goes with its last drawn part.
fn draw_series<'a, 'b: 'a>(context: &mut Context<'a, 'b>, series: &Series) -> Result<(), DrawError> {
    let color = series.tone.color();
    let style = ShapeStyle::from(color).stroke_width(2);
    let mark = series.mark;
    let s = MARKER_SIZE;
    let annotation = match mark {
        Mark::Line | Mark::Dashed => {
            let mut segments = series.segments();
            let Some(last) = segments.pop() else { return Ok(()) };
            for segment in segments {
                draw_line(context, segment, mark, style)?;
            }
            draw_line(context, last, mark, style)?
        }
        _ => {
            let points: Vec<(f64, f64)> = series.finite_points().collect();
            match mark {
                Mark::Squares => context.draw_series(points.into_iter().map(|p| EmptyElement::at(p) + Rectangle::new([(-s, -s), (s, s)], style)))?,
                Mark::Triangles => context.draw_series(points.into_iter().map(|p| TriangleMarker::new(p, s + 1, color.filled())))?,
                Mark::Dots => context.draw_series(points.into_iter().map(|p| Circle::new(p, DOT_SIZE, color.filled())))?,
                _ => context.draw_series(points.into_iter().map(|p| Circle::new(p, s, color.filled())))?,
            }
        }
    };
    if !series.label.is_empty() {
        annotation.label(&series.label).legend(move |(x, y)| legend_symbol(mark, (x, y), style));
    }
    Ok(())
}

fn draw_line<'c, 'a, 'b: 'a>(context: &'c mut Context<'a, 'b>, segment: Vec<(f64, f64)>, mark: Mark, style: ShapeStyle) -> Result<Annotation<'c, 'a, 'b>, DrawError> {
    match mark {
        Mark::Dashed => context.draw_series(DashedLineSeries::new(segment, 8, 5, style)),
        _ => context.draw_series(LineSeries::new(segment, style)),
    }
}

/// The legend's sample of a series' mark at `(x, y)`.
fn legend_symbol<'b>(mark: Mark, (x, y): (i32, i32), style: ShapeStyle) -> DynElement<'static, SVGBackend<'b>, (i32, i32)> {
    let s = MARKER_SIZE;
    match mark {
        Mark::Line => PathElement::new(vec![(x, y), (x + 20, y)], style).into_dyn(),
        Mark::Dashed => plotters::element::DashedPathElement::new(vec![(x, y), (x + 20, y)], 7, 5, style).into_dyn(),
        Mark::Squares => Rectangle::new([(x + 10 - s, y - s), (x + 10 + s, y + s)], style).into_dyn(),
        Mark::Triangles => TriangleMarker::new((x + 10, y), s + 1, style.filled()).into_dyn(),
        Mark::Dots | Mark::Circles => Circle::new((x + 10, y), s, style.filled()).into_dyn(),
    }
}

/// Height of the plotting area, px (the chart less caption, x labels and margins), and of a
/// legend's frame and of each of its entries.
const PLOT_HEIGHT: f64 = 450.0;
const LEGEND_FRAME: f64 = 20.0;
const LEGEND_ENTRY: f64 = 18.0;

/// `range` raised at the top so that a legend of `entries` entries in the upper right corner
/// sits above the data (at most doubling the range).
fn with_legend_headroom((low, high): (f64, f64), entries: usize) -> (f64, f64) {
    if entries == 0 {
        return (low, high);
    }
    let fraction = ((LEGEND_FRAME + LEGEND_ENTRY * entries as f64) / PLOT_HEIGHT).min(0.5);
    (low, high + (high - low) * fraction / (1.0 - fraction))
}

/// [min, max] of the finite values widened by 5 % of their span each side (by 5 % of the value,
/// or 1, when all are equal); `None` without a finite value.
fn padded_range(values: impl Iterator<Item = f64>) -> Option<(f64, f64)> {
    let (low, high) = values.filter(|v| v.is_finite()).fold(None, |range: Option<(f64, f64)>, v| {
        Some(range.map_or((v, v), |(low, high)| (low.min(v), high.max(v))))
    })?;
    let margin = if high > low { 0.05 * (high - low) } else if low != 0.0 { 0.05 * low.abs() } else { 1.0 };
    Some((low - margin, high + margin))
}
