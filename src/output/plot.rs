//! Line charts as PNG (bitmap backend, embedded DejaVu Sans) and SVG, one file pair per figure:
//! the one drawing routine of the crate (the report's figures, the trade-off figures, the fit
//! example's).

use crate::app_error::AppError;
use plotters::coord::ranged1d::ValueFormatter;
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::FontStyle;
use std::path::Path;
use std::sync::Once;

/// How a series is drawn.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Stroke {
    /// Solid line.
    Solid,
    /// Dashed line.
    Dashed,
    /// Dotted line.
    Dotted,
    /// Open circles at the points, no line.
    Markers,
    /// Filled circles at the points, no line.
    Filled,
}

/// The axes of a panel.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Scale {
    /// Linear x and y.
    #[default]
    Linear,
    /// Logarithmic x and y (labels in powers of ten).
    LogLog,
}

/// One curve.
#[derive(Debug, Clone)]
pub struct Series {
    /// Legend entry (empty: none).
    pub label: String,
    /// (x, y) points.
    pub points: Vec<(f64, f64)>,
    /// Line style.
    pub stroke: Stroke,
    /// Colour index into the palette, or [`GREY`].
    pub colour: usize,
    /// Text written next to each point (markers).
    pub annotation: Option<String>,
}

impl Series {
    /// A series without annotation.
    pub fn new(
        label: impl Into<String>,
        points: Vec<(f64, f64)>,
        stroke: Stroke,
        colour: usize,
    ) -> Self {
        Self {
            label: label.into(),
            points,
            stroke,
            colour,
            annotation: None,
        }
    }
}

/// One chart.
#[derive(Debug, Clone)]
pub struct Panel {
    /// Caption above the chart.
    pub title: String,
    /// x-axis label (with unit).
    pub x_label: String,
    /// y-axis label (with unit).
    pub y_label: String,
    /// Curves.
    pub series: Vec<Series>,
    /// Fixed x range (default: the data's, padded).
    pub x_range: Option<(f64, f64)>,
    /// Fixed y range (default: the data's, padded).
    pub y_range: Option<(f64, f64)>,
    /// The axes.
    pub scale: Scale,
}

/// A figure: one or more panels stacked vertically.
#[derive(Debug, Clone)]
pub struct Figure {
    /// File stem (`fig_active_curve` → `.png`, `.svg`).
    pub stem: String,
    /// Heading in the report.
    pub heading: String,
    /// What the figure shows and how it relates to the chapter.
    pub caption: String,
    /// Panels, top to bottom.
    pub panels: Vec<Panel>,
}

/// A figure with the bytes of its PNG (for embedding in a report).
pub type Rendered = (Figure, Vec<u8>);

const PALETTE: [RGBColor; 8] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(23, 190, 207),
];

/// The colour index of grey (outside the palette's cycle).
pub const GREY: usize = usize::MAX;

fn colour(index: usize) -> RGBColor {
    if index == GREY {
        RGBColor(120, 120, 120)
    } else {
        PALETTE[index % PALETTE.len()]
    }
}

static FONT: &[u8] = include_bytes!("../../assets/DejaVuSans.ttf");
static REGISTER: Once = Once::new();

/// Registers the embedded font as "sans-serif" (once per process).
fn register_font() {
    REGISTER.call_once(|| {
        // An invalid font would only lose the text of the PNGs; the SVGs do not need it.
        let _ = plotters::style::register_font("sans-serif", FontStyle::Normal, FONT);
    });
}

const PANEL_SIZE: (u32, u32) = (900, 560);

/// Writes `figure` as the PNG `png` and the SVG `svg`.
pub fn render(figure: &Figure, png: &Path, svg: &Path) -> Result<(), AppError> {
    register_font();
    let size = (
        PANEL_SIZE.0,
        PANEL_SIZE.1 * figure.panels.len().max(1) as u32,
    );
    let err = |what: &str, e: String| AppError::Output {
        file: figure.stem.clone(),
        message: format!("{what}: {e}"),
    };
    {
        let root = BitMapBackend::new(png, size).into_drawing_area();
        draw(&root, figure).map_err(|e| err("drawing PNG", e))?;
        root.present()
            .map_err(|e| err("writing PNG", e.to_string()))?;
    }
    let mut text = String::new();
    {
        let root = SVGBackend::with_string(&mut text, size).into_drawing_area();
        draw(&root, figure).map_err(|e| err("drawing SVG", e))?;
        root.present()
            .map_err(|e| err("writing SVG", e.to_string()))?;
    }
    std::fs::write(svg, text).map_err(|e| AppError::io("write", svg, e))
}

fn draw<DB: DrawingBackend>(root: &DrawingArea<DB, Shift>, figure: &Figure) -> Result<(), String> {
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let areas = root.split_evenly((figure.panels.len().max(1), 1));
    for (area, panel) in areas.iter().zip(&figure.panels) {
        draw_panel(area, panel)?;
    }
    Ok(())
}

fn bounds(panel: &Panel) -> ((f64, f64), (f64, f64)) {
    let pts = panel.series.iter().flat_map(|s| s.points.iter());
    let (mut x0, mut x1, mut y0, mut y1) = (
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    );
    for &(x, y) in pts {
        if x.is_finite() && y.is_finite() {
            x0 = x0.min(x);
            x1 = x1.max(x);
            y0 = y0.min(y);
            y1 = y1.max(y);
        }
    }
    if !x0.is_finite() {
        return (
            panel.x_range.unwrap_or((0.0, 1.0)),
            panel.y_range.unwrap_or((0.0, 1.0)),
        );
    }
    let pad = |a: f64, b: f64, f: f64| {
        let w = (b - a).abs().max(1e-9);
        (a - f * w, b + f * w)
    };
    let x = panel.x_range.unwrap_or_else(|| pad(x0, x1, 0.02));
    let y = panel.y_range.unwrap_or_else(|| pad(y0, y1, 0.05));
    (x, y)
}

fn draw_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    panel: &Panel,
) -> Result<(), String> {
    let ((x0, x1), (y0, y1)) = bounds(panel);
    let e = |x: DrawingAreaErrorKind<DB::ErrorType>| x.to_string();
    let mut builder = ChartBuilder::on(area);
    builder
        .caption(&panel.title, ("sans-serif", 22))
        .margin(14)
        .x_label_area_size(48)
        .y_label_area_size(70);
    match panel.scale {
        Scale::Linear => {
            let mut chart: ChartContext<DB, Cartesian2d<RangedCoordf64, RangedCoordf64>> =
                builder.build_cartesian_2d(x0..x1, y0..y1).map_err(e)?;
            mesh(&mut chart, panel, None)?;
            draw_series(&mut chart, panel, y0, y1)
        }
        Scale::LogLog => {
            let mut chart = builder
                .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())
                .map_err(e)?;
            mesh(&mut chart, panel, Some(&|v: &f64| format!("{v:.0e}")))?;
            draw_series(&mut chart, panel, y0, y1)
        }
    }
}

/// The grid, the tick labels (in `format` if given) and the axis labels of `panel`.
fn mesh<'a, DB, X, Y>(
    chart: &mut ChartContext<'a, DB, Cartesian2d<X, Y>>,
    panel: &Panel,
    format: Option<&dyn Fn(&f64) -> String>,
) -> Result<(), String>
where
    DB: DrawingBackend + 'a,
    X: Ranged<ValueType = f64> + ValueFormatter<f64>,
    Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    let mut m = chart.configure_mesh();
    m.x_desc(panel.x_label.as_str())
        .y_desc(panel.y_label.as_str())
        .label_style(("sans-serif", 16))
        .axis_desc_style(("sans-serif", 18));
    if let Some(f) = format {
        m.x_label_formatter(f).y_label_formatter(f);
    }
    m.light_line_style(RGBColor(235, 235, 235))
        .draw()
        .map_err(|x| x.to_string())
}

/// The series of `panel` and their legend, on any axes.
fn draw_series<'a, DB, X, Y>(
    chart: &mut ChartContext<'a, DB, Cartesian2d<X, Y>>,
    panel: &Panel,
    y0: f64,
    y1: f64,
) -> Result<(), String>
where
    DB: DrawingBackend + 'a,
    X: Ranged<ValueType = f64>,
    Y: Ranged<ValueType = f64>,
{
    let e = |x: DrawingAreaErrorKind<DB::ErrorType>| x.to_string();
    for s in &panel.series {
        let c = colour(s.colour);
        let style = c.stroke_width(2);
        let stroke = s.stroke;
        for (i, pts) in runs(s, y0, y1).into_iter().enumerate() {
            if let Some(text) = &s.annotation {
                chart
                    .draw_series(pts.iter().map(|&p| {
                        EmptyElement::at(p) + Text::new(text.clone(), (8, -18), ("sans-serif", 14))
                    }))
                    .map_err(e)?;
            }
            let a = match s.stroke {
                Stroke::Solid => chart.draw_series(LineSeries::new(pts, style)),
                Stroke::Dashed => chart.draw_series(DashedLineSeries::new(pts, 9, 6, style)),
                Stroke::Dotted => chart.draw_series(DottedLineSeries::new(pts, 0, 7, move |p| {
                    Circle::new(p, 2, c.filled())
                })),
                Stroke::Markers => chart.draw_series(
                    pts.into_iter()
                        .map(|p| Circle::new(p, 4, c.stroke_width(2))),
                ),
                Stroke::Filled => {
                    chart.draw_series(pts.into_iter().map(|p| Circle::new(p, 5, c.filled())))
                }
            }
            .map_err(e)?;
            // Only the first run carries the legend entry; an empty label has none.
            if i > 0 || s.label.is_empty() {
                continue;
            }
            a.label(s.label.as_str())
                .legend(move |(x, y)| match stroke {
                    Stroke::Markers => Circle::new((x + 10, y), 4, c.stroke_width(2)).into_dyn(),
                    Stroke::Filled => Circle::new((x + 10, y), 5, c.filled()).into_dyn(),
                    Stroke::Solid => {
                        PathElement::new(vec![(x, y), (x + 20, y)], c.stroke_width(2)).into_dyn()
                    }
                    // Composed legend glyphs would need a 'static backend: a short segment
                    // stands for a dashed line and a small dot for a dotted one.
                    Stroke::Dashed => {
                        PathElement::new(vec![(x + 5, y), (x + 14, y)], c.stroke_width(2))
                            .into_dyn()
                    }
                    Stroke::Dotted => Circle::new((x + 10, y), 2, c.filled()).into_dyn(),
                });
        }
    }
    legend_box(chart, panel.scale)
}

/// The legend: upper left on linear axes; lower left on log–log axes, where error against time
/// falls from upper left to lower right.
fn legend_box<'a, DB, X, Y>(
    chart: &mut ChartContext<'a, DB, Cartesian2d<X, Y>>,
    scale: Scale,
) -> Result<(), String>
where
    DB: DrawingBackend + 'a,
    X: Ranged<ValueType = f64>,
    Y: Ranged<ValueType = f64>,
{
    chart
        .configure_series_labels()
        .position(match scale {
            Scale::Linear => SeriesLabelPosition::UpperLeft,
            Scale::LogLog => SeriesLabelPosition::LowerLeft,
        })
        .label_font(("sans-serif", 15))
        .background_style(WHITE.mix(0.85))
        .border_style(RGBColor(180, 180, 180))
        .draw()
        .map_err(|e| e.to_string())
}

/// The point runs of a series inside y ∈ [y0, y1]: a line is clipped into runs; markers outside
/// the frame are dropped, not moved onto its edge.
fn runs(s: &Series, y0: f64, y1: f64) -> Vec<Vec<(f64, f64)>> {
    if matches!(s.stroke, Stroke::Markers | Stroke::Filled) {
        vec![s
            .points
            .iter()
            .copied()
            .filter(|&(x, y)| x.is_finite() && y >= y0 && y <= y1)
            .collect()]
    } else {
        clip(&s.points, y0, y1)
    }
}

/// Splits a polyline into the runs that lie within y ∈ [lo, hi], with the crossing points
/// interpolated onto the bounds (so a curve leaves the frame instead of running along its edge).
fn clip(points: &[(f64, f64)], lo: f64, hi: f64) -> Vec<Vec<(f64, f64)>> {
    let inside = |y: f64| y >= lo && y <= hi;
    let cross = |a: (f64, f64), b: (f64, f64)| -> (f64, f64) {
        let bound = if b.1 > hi || a.1 > hi { hi } else { lo };
        let t = (bound - a.1) / (b.1 - a.1);
        (a.0 + t * (b.0 - a.0), bound)
    };
    let pts: Vec<(f64, f64)> = points
        .iter()
        .copied()
        .filter(|(x, y)| x.is_finite() && y.is_finite())
        .collect();
    let mut runs = Vec::new();
    let mut cur: Vec<(f64, f64)> = Vec::new();
    for (i, &p) in pts.iter().enumerate() {
        let prev = i.checked_sub(1).map(|j| pts[j]);
        match (inside(p.1), prev) {
            (true, Some(q)) if !inside(q.1) => cur.push(cross(q, p)),
            (false, Some(q)) if inside(q.1) => {
                cur.push(cross(q, p));
                runs.push(std::mem::take(&mut cur));
            }
            _ => {}
        }
        if inside(p.1) {
            cur.push(p);
        }
    }
    if !cur.is_empty() {
        runs.push(cur);
    }
    runs
}
