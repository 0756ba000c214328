//! Line charts as PNG (bitmap backend, embedded DejaVu Sans) and SVG, one file pair per figure:
//! the one drawing routine of the crate (the report's figures, the trade-off figures, the fit
//! example's).

use crate::app_error::AppError;
use crate::text::{significant, trim_zeros};
use plotters::coord::ranged1d::ValueFormatter;
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use plotters::style::FontStyle;
use std::path::Path;
use std::sync::Once;

/// What tells one curve of `curves.csv` from the others: every column but the point's values,
/// and γ for a constant-γ curve (`study | model | direction | bases | energy | law | coupling | d
/// | γ`, empty cells empty). The figures mark the series that draw a curve with it.
#[derive(Debug, Clone, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct CurveId(pub String);

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
    /// Linear x, logarithmic y (labels in powers of ten): curves that grow exponentially, side
    /// by side over many decades; values ≤ 0 are not drawn.
    LogY,
    /// Linear x and y, x counting states (1, 2, 3, …): tick labels at whole numbers only.
    Counted,
    /// Logarithmic y as [`Scale::LogY`], x counting (Newton iterations 0, 1, 2, …) as
    /// [`Scale::Counted`].
    CountedLogY,
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
    /// The curve of `curves.csv` this series draws, if it draws one (checked: every curve of
    /// `curves.csv` is drawn with a legend entry).
    pub curve: Option<CurveId>,
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
            curve: None,
        }
    }

    /// The same series, marked as drawing the curve `id` of `curves.csv`.
    pub fn drawing(mut self, id: CurveId) -> Self {
        self.curve = Some(id);
        self
    }

    /// Finite points.
    fn finite(&self) -> impl Iterator<Item = (f64, f64)> + '_ {
        self.points
            .iter()
            .copied()
            .filter(|(x, y)| x.is_finite() && y.is_finite())
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
    /// Fixed y range (default: the data's, padded, clipped where a curve blows up: see
    /// [`Panel::frame`]).
    pub y_range: Option<(f64, f64)>,
    /// The axes.
    pub scale: Scale,
}

/// The ranges a panel is drawn on, and what they leave out.
#[derive(Debug, Clone, PartialEq)]
pub struct Frame {
    /// x range.
    pub x: (f64, f64),
    /// y range.
    pub y: (f64, f64),
    /// Whether the data rise above `y.1` (the y axis was clipped there).
    pub clipped_above: bool,
    /// Whether the data fall below `y.0`.
    pub clipped_below: bool,
}

impl Frame {
    /// Whether `(x, y)` is drawn.
    pub fn contains(&self, (x, y): (f64, f64)) -> bool {
        x >= self.x.0 && x <= self.x.1 && y >= self.y.0 && y <= self.y.1
    }
}

/// The `q`-quantile (0 ≤ q ≤ 1) of sorted values (nearest rank).
fn quantile(sorted: &[f64], q: f64) -> f64 {
    sorted[((sorted.len() - 1) as f64 * q).round() as usize]
}

/// How far a curve reaches beyond its own interquartile range before the rest of it counts as a
/// blow-up, in interquartile ranges; and how far above the curves that do not blow up the frame
/// reaches into one that does, in their own height.
const CLIP_REACH: f64 = 2.0;

/// Fewer points than this tell nothing of a blow-up: such a curve is drawn whole.
const MIN_POINTS: usize = 8;

/// A curve blows up only if its maximum lies this many times further above its median than the
/// level where it would be cut (an exponential ending at 17 kPa, cut at 6.7, is drawn whole).
const BLOW_UP: f64 = 3.0;

/// Where a linear y axis is cut above, if a curve blows up: `None` if none does. `curves` are
/// each curve's values, sorted.
///
/// A curve blows up when it has [`MIN_POINTS`] points or more and its maximum lies above
/// q75 + [`CLIP_REACH`] · (q75 − q25) of its own values, [`BLOW_UP`] times as far from its median (the passive exponential reaches 10⁴ kPa at λ = 1.6 where the active features are tens
/// of kPa). The cut is at that level, taken as the upper median over the curves that blow up
/// (one that blows up early does not set the scale of the others); if some curves do not blow
/// up, at most [`CLIP_REACH`] times their height above their maximum and never below it: they
/// stay whole in the frame. It keeps every curve's lowest tenth and y = 0 in view.
fn limit(curves: &[Vec<f64>]) -> Option<f64> {
    let mut calm: Option<f64> = None;
    let mut tops = Vec::new();
    let mut tenth = f64::NEG_INFINITY;
    for c in curves {
        let (q25, q75) = (quantile(c, 0.25), quantile(c, 0.75));
        let top = q75 + CLIP_REACH * (q75 - q25);
        let max = c[c.len() - 1];
        tenth = tenth.max(quantile(c, 0.1));
        // A curve that ends at most BLOW_UP times as far above its median as `top` is drawn
        // whole: cutting it would hide its end to gain little height.
        let q50 = quantile(c, 0.5);
        if c.len() >= MIN_POINTS && max > top && max - q50 > BLOW_UP * (top - q50) {
            tops.push(top);
        } else {
            calm = Some(calm.map_or(max, |m| m.max(max)));
        }
    }
    if tops.is_empty() {
        return None;
    }
    tops.sort_by(f64::total_cmp);
    let blown = tops[tops.len() / 2];
    let cut = match calm {
        Some(m) => m.max(blown.min(m + CLIP_REACH * m.abs())),
        None => blown,
    };
    Some(cut.max(tenth).max(0.0))
}

impl Panel {
    /// A linear panel with ranges from its data.
    pub fn new(
        title: impl Into<String>,
        x_label: impl Into<String>,
        y_label: impl Into<String>,
        series: Vec<Series>,
    ) -> Self {
        Self {
            title: title.into(),
            x_label: x_label.into(),
            y_label: y_label.into(),
            series,
            x_range: None,
            y_range: None,
            scale: Scale::Linear,
        }
    }

    /// The pairs of series (earlier, later) the panel cannot tell apart: the same x values and
    /// the largest |Δy| within `fraction` of the larger |y| of the two (the later one, drawn on
    /// top, hides the earlier), with that largest |Δy|.
    pub fn coinciding(&self, fraction: f64) -> Vec<(usize, usize, f64)> {
        let mut pairs = Vec::new();
        for (i, a) in self.series.iter().enumerate() {
            for (j, b) in self.series.iter().enumerate().skip(i + 1) {
                if a.points.is_empty() || a.points.len() != b.points.len() {
                    continue;
                }
                let (mut diff, mut scale, mut same_x) = (0.0_f64, 0.0_f64, true);
                for (p, q) in a.points.iter().zip(&b.points) {
                    same_x &= p.0 == q.0;
                    diff = diff.max((p.1 - q.1).abs());
                    scale = scale.max(p.1.abs()).max(q.1.abs());
                }
                if same_x && diff <= fraction * scale {
                    pairs.push((i, j, diff));
                }
            }
        }
        pairs
    }

    /// [a, b] widened by the fraction `f` of its width each way. A range narrower than a
    /// millionth of its magnitude (a constant series) would print the same tick label
    /// everywhere: it is opened to ±10 % of the value (±1 around 0).
    fn pad(a: f64, b: f64, f: f64) -> (f64, f64) {
        let m = a.abs().max(b.abs());
        if (b - a).abs() <= 1e-6 * m || m == 0.0 {
            let h = if m > 0.0 { 0.1 * m } else { 1.0 };
            return (a - h, b + h);
        }
        let w = (b - a).abs();
        (a - f * w, b + f * w)
    }

    /// The ranges the panel is drawn on. x: the data's (padded 2 %) unless fixed. y, unless fixed:
    /// on a log axis the positive data's; on a linear axis the data's (padded 5 %), cut where
    /// curves blow up (see `limit`), never so that y = 0 leaves the frame.
    pub fn frame(&self) -> Frame {
        let log = matches!(self.scale, Scale::LogLog | Scale::LogY | Scale::CountedLogY);
        let (mut x0, mut x1) = (f64::INFINITY, f64::NEG_INFINITY);
        // Every series' sorted values, and whether it is a line (markers often mark parts of
        // other curves: only lines set where the axis is cut, unless there are none).
        let mut curves: Vec<(Vec<f64>, bool)> = Vec::new();
        for s in &self.series {
            let mut own: Vec<f64> = s
                .finite()
                .map(|p| p.1)
                .filter(|&y| !log || y > 0.0)
                .collect();
            if own.is_empty() {
                continue;
            }
            own.sort_by(f64::total_cmp);
            for (x, _) in s.finite() {
                x0 = x0.min(x);
                x1 = x1.max(x);
            }
            curves.push((own, !matches!(s.stroke, Stroke::Markers | Stroke::Filled)));
        }
        if curves.is_empty() {
            return Frame {
                x: self.x_range.unwrap_or((0.0, 1.0)),
                y: self
                    .y_range
                    .unwrap_or(if log { (1e-3, 1.0) } else { (0.0, 1.0) }),
                clipped_above: false,
                clipped_below: false,
            };
        }
        let lo = curves.iter().map(|c| c.0[0]).fold(f64::INFINITY, f64::min);
        let hi = curves
            .iter()
            .map(|c| c.0[c.0.len() - 1])
            .fold(f64::NEG_INFINITY, f64::max);
        let x = self.x_range.unwrap_or_else(|| Self::pad(x0, x1, 0.02));
        if let Some(y) = self.y_range {
            return Frame {
                x,
                y,
                clipped_above: hi > y.1,
                clipped_below: lo < y.0,
            };
        }
        if log {
            return Frame {
                x,
                y: (lo / 2.0, hi * 2.0),
                clipped_above: false,
                clipped_below: false,
            };
        }
        let lines = curves.iter().any(|c| c.1);
        let curves: Vec<Vec<f64>> = curves
            .into_iter()
            .filter(|c| c.1 || !lines)
            .map(|c| c.0)
            .collect();
        let top = limit(&curves).filter(|&t| hi > t);
        let negated: Vec<Vec<f64>> = curves
            .iter()
            .map(|c| c.iter().rev().map(|y| -y).collect())
            .collect();
        let bottom = limit(&negated).map(|b| -b).filter(|&b| lo < b);
        let (a, b) = Self::pad(bottom.unwrap_or(lo), top.unwrap_or(hi), 0.05);
        Frame {
            x,
            y: (bottom.unwrap_or(a), top.unwrap_or(b)),
            clipped_above: top.is_some(),
            clipped_below: bottom.is_some(),
        }
    }

    /// Where `frame` cuts the y axis (above: true), with how far the curves go beyond the cut:
    /// `on up to 17kPa at λ = 1.6`. Drawn on the figure and said in its caption.
    fn cuts(&self, frame: &Frame) -> Vec<(bool, String)> {
        let symbol = axis_symbol(&self.x_label);
        let unit = axis_unit(&self.y_label);
        let extreme = |above: bool| {
            self.series
                .iter()
                .flat_map(Series::finite)
                .max_by(|a, b| {
                    if above {
                        a.1.total_cmp(&b.1)
                    } else {
                        b.1.total_cmp(&a.1)
                    }
                })
                .unwrap_or((f64::NAN, f64::NAN))
        };
        [(true, frame.clipped_above), (false, frame.clipped_below)]
            .into_iter()
            .filter(|&(_, cut)| cut)
            .map(|(above, _)| {
                let (x, y) = extreme(above);
                let way = if above { "on up to" } else { "down to" };
                (
                    above,
                    format!("{way} {}{unit} at {symbol} = {}", short(y), short(x)),
                )
            })
            .collect()
    }

    /// What the frame leaves out, in words: a clipped axis with how far the data go, and every
    /// labelled series with no point inside the frame.
    pub fn notes(&self) -> Vec<String> {
        let f = self.frame();
        let unit = axis_unit(&self.y_label);
        let mut notes: Vec<String> = self
            .cuts(&f)
            .into_iter()
            .map(|(above, reach)| {
                let edge = if above { f.y.1 } else { f.y.0 };
                format!(
                    "{}: y axis cut at {}{unit} (the curves go {reach})",
                    self.title,
                    short(edge)
                )
            })
            .collect();
        if matches!(self.scale, Scale::LogY | Scale::CountedLogY)
            && self
                .series
                .iter()
                .flat_map(Series::finite)
                .any(|p| p.1 <= 0.0)
        {
            notes.push(format!("{}: values ≤ 0 (not on the log axis)", self.title));
        }
        for s in &self.series {
            if !s.label.is_empty() && !s.points.is_empty() && !s.finite().any(|p| f.contains(p)) {
                notes.push(format!(
                    "{}: \"{}\" lies outside this frame",
                    self.title, s.label
                ));
            }
        }
        notes
    }
}

/// The unit of an axis label, with a leading space: `P [kPa]` → ` kPa`; none for `[-]`.
pub fn axis_unit(label: &str) -> String {
    match label.split_once('[').and_then(|(_, u)| u.split_once(']')) {
        Some((u, _)) if u != "-" && !u.is_empty() => format!(" {u}"),
        _ => String::new(),
    }
}

/// The symbol of an axis label: `stretch λ [-]` → `λ`.
fn axis_symbol(label: &str) -> &str {
    label
        .split('[')
        .next()
        .and_then(|s| s.split_whitespace().last())
        .unwrap_or("x")
}

/// A number in four significant digits (whole below 1e5) without trailing zeros, scientific
/// outside [1e-3, 1e5):
/// `0.1`, `-2.5`, `1.628e5`, `2e-12`, `0` (also for −0).
pub fn short(x: f64) -> String {
    if x == 0.0 || (1e-3..1e5).contains(&x.abs()) {
        significant(x, 4)
    } else {
        let s = format!("{x:.3e}");
        let (mantissa, exponent) = s.split_once('e').unwrap_or((&s, "0"));
        format!("{}e{exponent}", trim_zeros(mantissa))
    }
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

impl Figure {
    /// Every `from` in the figure's words (heading, caption, panel titles and axis labels,
    /// series labels) replaced by `to`: the activation variable's symbol, γ or ω.
    pub fn rename_symbol(&mut self, from: &str, to: &str) {
        let swap = |t: &mut String| *t = t.replace(from, to);
        swap(&mut self.heading);
        swap(&mut self.caption);
        for p in &mut self.panels {
            swap(&mut p.title);
            swap(&mut p.x_label);
            swap(&mut p.y_label);
            for s in &mut p.series {
                swap(&mut s.label);
            }
        }
    }

    /// A figure whose caption ends with what its frames leave out ([`Panel::notes`]).
    pub fn new(
        stem: impl Into<String>,
        heading: impl Into<String>,
        caption: impl Into<String>,
        panels: Vec<Panel>,
    ) -> Self {
        let mut caption: String = caption.into();
        let notes: Vec<String> = panels.iter().flat_map(Panel::notes).collect();
        if !notes.is_empty() {
            caption.push_str(&format!(" Not in the frame: {}.", notes.join("; ")));
        }
        Self {
            stem: stem.into(),
            heading: heading.into(),
            caption,
            panels,
        }
    }

    /// Every series of every panel.
    pub fn series(&self) -> impl Iterator<Item = &Series> {
        self.panels.iter().flat_map(|p| p.series.iter())
    }
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

static FONT: &[u8] = include_bytes!("../assets/DejaVuSans.ttf");
static REGISTER: Once = Once::new();

/// Registers the embedded font as "sans-serif" (once per process).
fn register_font() {
    REGISTER.call_once(|| {
        // An invalid font would only lose the text of the PNGs; the SVGs do not need it.
        let _ = plotters::style::register_font("sans-serif", FontStyle::Normal, FONT);
    });
}

/// Plot area of one panel \[px\] (the legend goes to its right).
const PANEL_SIZE: (u32, u32) = (900, 560);
/// Legend text size \[px\], height of one entry, width of the glyph before the text.
const LEGEND_FONT: u32 = 15;
const LEGEND_ROW: u32 = 21;
const LEGEND_GLYPH: u32 = 34;

/// Columns a legend may take: a wider one would make the figure wider than a screen.
const MAX_LEGEND_COLUMNS: usize = 3;

/// The legend of a panel of height `h`: its labelled series, at most [`MAX_LEGEND_COLUMNS`]
/// columns of them; when there are more, the last place says how many are left out.
struct Legend<'a> {
    shown: Vec<&'a Series>,
    left_out: usize,
}

impl<'a> Legend<'a> {
    fn of(panel: &'a Panel, h: u32) -> Self {
        let mut shown: Vec<&Series> = panel
            .series
            .iter()
            .filter(|s| !s.label.is_empty())
            .collect();
        let room = MAX_LEGEND_COLUMNS * legend_rows(h);
        let left_out = if shown.len() > room {
            let n = shown.len() - (room - 1);
            shown.truncate(room - 1);
            n
        } else {
            0
        };
        Self { shown, left_out }
    }

    /// The entry that stands for the series left out.
    fn more(&self) -> Option<String> {
        (self.left_out > 0).then(|| format!("… {} more (in the CSV)", self.left_out))
    }

    /// Entries, the "more" line counted.
    fn len(&self) -> usize {
        self.shown.len() + usize::from(self.left_out > 0)
    }
}

/// Rows of a legend column in a panel of height `h`.
fn legend_rows(h: u32) -> usize {
    ((h.saturating_sub(70)) / LEGEND_ROW).max(1) as usize
}

/// Width \[px\] of the legend of `panel` (0 without entries), in columns of at most
/// [`legend_rows`] entries.
fn legend_width(panel: &Panel, h: u32) -> u32 {
    let legend = Legend::of(panel, h);
    let widest = legend
        .shown
        .iter()
        .map(|s| s.label.clone())
        .chain(legend.more())
        .map(|label| {
            ("sans-serif", LEGEND_FONT)
                .into_font()
                .box_size(&label)
                .map_or(8 * label.chars().count() as u32, |b| b.0)
        })
        .max();
    widest.map_or(0, |w| {
        let columns = legend.len().div_ceil(legend_rows(h)) as u32;
        columns * (w + LEGEND_GLYPH + 16) + 8
    })
}

/// Writes `figure` as the PNG `png` and the SVG `svg`: the panels stacked, each with its legend
/// to the right of its plot area, outside the data.
pub fn render(figure: &Figure, png: &Path, svg: &Path) -> Result<(), AppError> {
    let (png_bytes, svg_text) = render_bytes(figure)?;
    std::fs::write(png, png_bytes).map_err(|e| AppError::io("write", png, e))?;
    std::fs::write(svg, svg_text).map_err(|e| AppError::io("write", svg, e))
}

/// `figure` drawn as [`render`] draws it, as the bytes of its PNG and the text of its SVG (for
/// a writer that reports its own I/O errors, e.g. a full disk).
pub fn render_bytes(figure: &Figure) -> Result<(Vec<u8>, String), AppError> {
    register_font();
    let h = if figure.panels.len() > 2 {
        PANEL_SIZE.1 * 4 / 5
    } else {
        PANEL_SIZE.1
    };
    let legend = figure
        .panels
        .iter()
        .map(|p| legend_width(p, h))
        .max()
        .unwrap_or(0);
    let size = (PANEL_SIZE.0 + legend, h * figure.panels.len().max(1) as u32);
    let err = |what: &str, e: String| AppError::Output {
        file: figure.stem.clone(),
        message: format!("{what}: {e}"),
    };
    let mut rgb = vec![0u8; 3 * size.0 as usize * size.1 as usize];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, size).into_drawing_area();
        draw(&root, figure).map_err(|e| err("drawing PNG", e))?;
        root.present()
            .map_err(|e| err("drawing PNG", e.to_string()))?;
    }
    let mut png = Vec::new();
    image::ImageEncoder::write_image(
        image::codecs::png::PngEncoder::new(&mut png),
        &rgb,
        size.0,
        size.1,
        image::ColorType::Rgb8,
    )
    .map_err(|e| err("encoding PNG", e.to_string()))?;
    let mut text = String::new();
    {
        let root = SVGBackend::with_string(&mut text, size).into_drawing_area();
        draw(&root, figure).map_err(|e| err("drawing SVG", e))?;
        root.present()
            .map_err(|e| err("writing SVG", e.to_string()))?;
    }
    Ok((png, text))
}

fn draw<DB: DrawingBackend>(root: &DrawingArea<DB, Shift>, figure: &Figure) -> Result<(), String> {
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let areas = root.split_evenly((figure.panels.len().max(1), 1));
    for (area, panel) in areas.iter().zip(&figure.panels) {
        let (plot, legend) = area.split_horizontally(PANEL_SIZE.0);
        draw_panel(&plot, panel)?;
        draw_legend(&legend, panel)?;
    }
    Ok(())
}

fn draw_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    panel: &Panel,
) -> Result<(), String> {
    let frame = panel.frame();
    let Frame {
        x: (x0, x1),
        y: (y0, y1),
        ..
    } = frame;
    let e = |x: DrawingAreaErrorKind<DB::ErrorType>| x.to_string();
    let mut builder = ChartBuilder::on(area);
    builder
        .caption(&panel.title, ("sans-serif", 22))
        .margin(14)
        .x_label_area_size(48)
        .y_label_area_size(78);
    match panel.scale {
        Scale::Linear | Scale::Counted => {
            let mut chart: ChartContext<DB, Cartesian2d<RangedCoordf64, RangedCoordf64>> =
                builder.build_cartesian_2d(x0..x1, y0..y1).map_err(e)?;
            // A tick at 0 computed as y0 + k·step may come out as −1.4e-17: written 0.
            let span = (y1 - y0).abs();
            let tick = |v: &f64| short(if v.abs() < 1e-9 * span { 0.0 } else { *v });
            let x_format: Option<&dyn Fn(&f64) -> String> = match panel.scale {
                Scale::Counted => Some(&whole),
                _ => None,
            };
            mesh(&mut chart, panel, x_format, Some(&tick))?;
            draw_series(&mut chart, panel, y0, y1)?;
            // A cut axis says so on the figure itself, along the cut edge, in the corner the
            // curves usually do not cross there (they blow up at large λ and dive at small λ).
            let font = ("sans-serif", 15).into_font().color(&RGBColor(150, 0, 0));
            for (above, reach) in panel.cuts(&frame) {
                let (at, pos) = if above {
                    ((x0, y1), Pos::new(HPos::Left, VPos::Top))
                } else {
                    ((x1, y0), Pos::new(HPos::Right, VPos::Bottom))
                };
                chart
                    .plotting_area()
                    .draw(&Text::new(
                        format!(" axis cut: the curves go {reach} "),
                        at,
                        font.pos(pos),
                    ))
                    .map_err(e)?;
            }
            Ok(())
        }
        Scale::LogLog => {
            let mut chart = builder
                .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())
                .map_err(e)?;
            mesh(&mut chart, panel, Some(&decade), Some(&decade))?;
            draw_series(&mut chart, panel, y0, y1)
        }
        Scale::LogY | Scale::CountedLogY => {
            let mut chart = builder
                .build_cartesian_2d(x0..x1, (y0..y1).log_scale())
                .map_err(e)?;
            let x_format: Option<&dyn Fn(&f64) -> String> =
                (panel.scale == Scale::CountedLogY).then_some(&whole);
            mesh(&mut chart, panel, x_format, Some(&decade))?;
            draw_series(&mut chart, panel, y0, y1)
        }
    }
}

/// A tick label on an axis that counts: whole numbers only (`5`, never `5.0`), other ticks
/// unlabelled.
fn whole(v: &f64) -> String {
    let n = v.round();
    if (v - n).abs() < 1e-9 {
        short(n)
    } else {
        String::new()
    }
}

/// A tick label on a log axis: powers of ten only (`1e-3`), other ticks unlabelled so that the
/// labels never run into each other.
fn decade(v: &f64) -> String {
    let exponent = v.log10().round();
    if (v / 10f64.powf(exponent) - 1.0).abs() < 1e-6 {
        format!("1e{exponent}")
    } else {
        String::new()
    }
}

/// The grid, the tick labels (x in `x_format`, y in `y_format` if given) and the axis labels of
/// `panel`.
fn mesh<'a, DB, X, Y>(
    chart: &mut ChartContext<'a, DB, Cartesian2d<X, Y>>,
    panel: &Panel,
    x_format: Option<&dyn Fn(&f64) -> String>,
    y_format: Option<&dyn Fn(&f64) -> String>,
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
    if let Some(f) = x_format {
        m.x_label_formatter(f);
    }
    if let Some(f) = y_format {
        m.y_label_formatter(f);
    }
    m.light_line_style(RGBColor(235, 235, 235))
        .draw()
        .map_err(|x| x.to_string())
}

/// The series of `panel`, on any axes.
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
        for pts in runs(s, y0, y1) {
            if let Some(text) = &s.annotation {
                chart
                    .draw_series(pts.iter().map(|&p| {
                        EmptyElement::at(p) + Text::new(text.clone(), (8, -18), ("sans-serif", 14))
                    }))
                    .map_err(e)?;
            }
            match s.stroke {
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
        }
    }
    Ok(())
}

/// The legend of `panel` in `area` (right of the plot): one row per labelled series, its glyph
/// (line, dashes, dots or circle in its colour) and its label, in columns of at most
/// [`legend_rows`] rows.
fn draw_legend<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    panel: &Panel,
) -> Result<(), String> {
    let e = |x: DrawingAreaErrorKind<DB::ErrorType>| x.to_string();
    let (_, h) = area.dim_in_pixel();
    let rows = legend_rows(h);
    let width = legend_width(panel, h);
    let legend = Legend::of(panel, h);
    let n = legend.len();
    if n == 0 {
        return Ok(());
    }
    let column = ((width - 8) / n.div_ceil(rows) as u32) as i32;
    let font = ("sans-serif", LEGEND_FONT).into_font().color(&BLACK);
    let place = |k: usize| {
        (
            4 + (k / rows) as i32 * column,
            52 + (k % rows) as i32 * LEGEND_ROW as i32,
        )
    };
    if let Some(more) = legend.more() {
        let (x, y) = place(n - 1);
        let at = (x + LEGEND_GLYPH as i32, y);
        area.draw_text(&more, &font.pos(Pos::new(HPos::Left, VPos::Center)), at)
            .map_err(e)?;
    }
    for (k, s) in legend.shown.iter().enumerate() {
        let (x, y) = place(k);
        let c = colour(s.colour);
        let line =
            |a: i32, b: i32| PathElement::new(vec![(x + a, y), (x + b, y)], c.stroke_width(2));
        match s.stroke {
            Stroke::Solid => area.draw(&line(0, 26)),
            Stroke::Dashed => area.draw(&line(0, 9)).and(area.draw(&line(15, 26))),
            Stroke::Dotted => [2, 11, 20]
                .iter()
                .try_for_each(|&a| area.draw(&Circle::new((x + a + 2, y), 2, c.filled()))),
            Stroke::Markers => area.draw(&Circle::new((x + 13, y), 4, c.stroke_width(2))),
            Stroke::Filled => area.draw(&Circle::new((x + 13, y), 5, c.filled())),
        }
        .map_err(e)?;
        area.draw_text(
            &s.label,
            &font.pos(Pos::new(HPos::Left, VPos::Center)),
            (x + LEGEND_GLYPH as i32, y),
        )
        .map_err(e)?;
    }
    Ok(())
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn short_numbers_have_four_significant_digits_whole_below_1e5_and_no_trailing_zeros() {
        for (x, text) in [
            (0.1, "0.1"),
            (-2.5, "-2.5"),
            (73.52, "73.52"),
            (0.62430001, "0.6243"),
            (15134.2, "15134"),
            (162754.79, "1.628e5"),
            (2e-12, "2e-12"),
            (-1.3878e-17, "-1.388e-17"),
            (0.0, "0"),
            (-0.0, "0"),
        ] {
            assert_eq!(short(x), text, "{x}");
        }
    }

    /// The x axis spans the plotted data (padded 2 % of their width each way) and nothing
    /// else: legend keys without points, and a curve cut off above by the y axis, do not
    /// widen it; every curve ends within the frame.
    #[test]
    fn the_x_range_is_the_extent_of_the_plotted_data() {
        let steep: Vec<(f64, f64)> = (0..=12)
            .map(|i| {
                let l = 0.8 + 0.05 * i as f64;
                (l, (20.0 * (l - 1.0)).exp())
            })
            .collect();
        let short: Vec<(f64, f64)> = (0..=6).map(|i| (0.9 + 0.05 * i as f64, 1.0)).collect();
        let panel = Panel::new(
            "P",
            "stretch λ [-]",
            "P [kPa]",
            vec![
                Series::new("steep", steep, Stroke::Solid, 0),
                Series::new("short", short, Stroke::Solid, 1),
                Series::new("(a key)", Vec::new(), Stroke::Solid, GREY),
            ],
        );
        let f = panel.frame();
        let (lo, hi) = (0.8, 0.8 + 0.05 * 12.0);
        let pad = 0.02 * (hi - lo);
        assert!(
            (f.x.0 - (lo - pad)).abs() < 1e-12 && (f.x.1 - (hi + pad)).abs() < 1e-12,
            "{f:?}"
        );
        assert!(f.clipped_above, "{f:?}");
    }

    /// A counting axis (Newton iterations) is labelled in whole numbers, `5`, never `5.0`, also
    /// beside a log y axis (whose labels are powers of ten).
    #[test]
    fn a_counting_axis_has_whole_number_tick_labels() {
        assert_eq!(whole(&5.0), "5");
        assert_eq!(whole(&0.0), "0");
        assert_eq!(whole(&2.5), "");
        for scale in [Scale::CountedLogY] {
            let residuals: Vec<(f64, f64)> = (0..7).map(|k| (k as f64, 10f64.powi(-k))).collect();
            let mut panel = Panel::new(
                "Newton",
                "Newton iteration [-]",
                "residual [-]",
                vec![Series::new("exact", residuals, Stroke::Solid, 0)],
            );
            panel.scale = scale;
            let figure = Figure::new("f", "f", "caption", vec![panel]);
            let (_, svg) = render_bytes(&figure).unwrap();
            // The text of every label: whole-number x ticks are there, decimal ones are not.
            let labels: Vec<&str> = svg
                .split("</text>")
                .filter_map(|t| t.rsplit('>').next().map(str::trim))
                .collect();
            for k in 0..=6 {
                assert!(
                    labels.contains(&k.to_string().as_str()),
                    "{scale:?}: {k} in {labels:?}"
                );
            }
            assert!(
                !labels
                    .iter()
                    .any(|l| l.ends_with(".0") || l.ends_with(".5")),
                "{scale:?}: {labels:?}"
            );
        }
    }

    /// An exponential that ends far above the rest is cut, and the figure files say so; one
    /// that ends within [`BLOW_UP`] of the cut is drawn whole.
    #[test]
    fn a_cut_axis_is_said_on_the_figure_and_a_modest_rise_is_not_cut() {
        let curve = || -> Vec<(f64, f64)> {
            (0..25)
                .map(|i| {
                    let l = 0.75 + 0.025 * i as f64;
                    (l, (20.0 * (l - 1.0)).exp() - 1.0)
                })
                .collect()
        };
        let panel = |points| {
            Panel::new(
                "P",
                "stretch λ [-]",
                "nominal stress P [kPa]",
                vec![Series::new("p", points, Stroke::Solid, 0)],
            )
        };
        // exp(20 (λ − 1)) − 1 on [0.75, 1.35]: ends at 1096 kPa, 400 × its median, cut.
        let steep = panel(curve());
        assert!(steep.frame().clipped_above);
        let dir = tempfile::tempdir().unwrap();
        let (png, svg) = (dir.path().join("f.png"), dir.path().join("f.svg"));
        let figure = Figure::new("f", "f", "caption", vec![steep]);
        render(&figure, &png, &svg).unwrap();
        let text = std::fs::read_to_string(&svg).unwrap();
        assert!(text.contains("axis cut: the curves go on up to 1096 kPa at λ = 1.35"));
        // A straight rise, then a mild upturn (the last points 2× the line's): whole.
        let mild: Vec<(f64, f64)> = (0..25)
            .map(|i| {
                let x = i as f64;
                (x, x + if i >= 22 { x } else { 0.0 })
            })
            .collect();
        assert!(!panel(mild).frame().clipped_above);
    }

    #[test]
    fn axis_labels_give_their_unit_and_symbol() {
        assert_eq!(axis_unit("nominal stress P [kPa]"), " kPa");
        assert_eq!(axis_unit("stretch λ [-]"), "");
        assert_eq!(axis_symbol("stretch λ [-]"), "λ");
    }
}
