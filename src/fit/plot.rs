//! Data versus fit, as PNG (bitmap backend; text in the embedded DejaVu Sans, registered with
//! plotters' `ab_glyph` feature so that no system font is needed) and SVG. Small and
//! self-contained on purpose.

use super::FitError;
use plotters::prelude::*;
use plotters::style::FontStyle;
use std::path::{Path, PathBuf};
use std::sync::Once;

static FONT: &[u8] = include_bytes!("../../assets/DejaVuSans.ttf");
static REGISTER: Once = Once::new();
const SIZE: (u32, u32) = (900, 600);
const COLOURS: [RGBColor; 4] = [
    RGBColor(214, 39, 40),
    RGBColor(31, 119, 180),
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
];

/// One figure: data points and model curves against λ.
#[derive(Debug, Clone, PartialEq)]
pub struct FitPlot {
    /// Caption.
    pub title: String,
    /// y-axis label with unit, e.g. "P \[kPa\]".
    pub y_label: String,
    /// Legend entry of the data.
    pub data_label: String,
    /// Data points (λ, y), drawn as circles.
    pub data: Vec<(f64, f64)>,
    /// Curves (legend entry, points), drawn as lines (the first solid, the others dashed).
    pub curves: Vec<(String, Vec<(f64, f64)>)>,
}

impl FitPlot {
    /// Writes `<stem>.png` and `<stem>.svg` (creating the directory) and returns both paths.
    pub fn write(&self, stem: &Path) -> Result<[PathBuf; 2], FitError> {
        REGISTER.call_once(|| {
            // A font that fails to load would cost only the PNG's text.
            let _ = plotters::style::register_font("sans-serif", FontStyle::Normal, FONT);
        });
        if let Some(dir) = stem.parent() {
            std::fs::create_dir_all(dir).map_err(|e| plot_error(stem, e))?;
        }
        let png = stem.with_extension("png");
        let svg = stem.with_extension("svg");
        {
            let root = BitMapBackend::new(&png, SIZE).into_drawing_area();
            self.draw(&root).map_err(|e| plot_error(&png, e))?;
            root.present().map_err(|e| plot_error(&png, e))?;
        }
        {
            let root = SVGBackend::new(&svg, SIZE).into_drawing_area();
            self.draw(&root).map_err(|e| plot_error(&svg, e))?;
            root.present().map_err(|e| plot_error(&svg, e))?;
        }
        Ok([png, svg])
    }

    fn draw<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, plotters::coord::Shift>,
    ) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
        root.fill(&WHITE)?;
        let all = self
            .data
            .iter()
            .chain(self.curves.iter().flat_map(|c| c.1.iter()));
        let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
        for &(x, y) in all.filter(|(x, y)| x.is_finite() && y.is_finite()) {
            (x0, x1, y0, y1) = (x0.min(x), x1.max(x), y0.min(y), y1.max(y));
        }
        if x0 > x1 {
            (x0, x1, y0, y1) = (0.0, 1.0, 0.0, 1.0);
        }
        let (dx, dy) = ((x1 - x0).max(1e-9) * 0.03, (y1 - y0).max(1e-9) * 0.05);
        let mut chart = ChartBuilder::on(root)
            .caption(&self.title, ("sans-serif", 24))
            .margin(15)
            .x_label_area_size(50)
            .y_label_area_size(70)
            .build_cartesian_2d((x0 - dx)..(x1 + dx), (y0 - dy)..(y1 + dy))?;
        chart
            .configure_mesh()
            .x_desc("stretch λ [-]")
            .y_desc(self.y_label.as_str())
            .label_style(("sans-serif", 16))
            .axis_desc_style(("sans-serif", 18))
            .draw()?;
        for (k, (label, points)) in self.curves.iter().enumerate() {
            let style = COLOURS[(k + 1) % COLOURS.len()].stroke_width(2);
            let series = if k == 0 {
                chart.draw_series(LineSeries::new(points.clone(), style))?
            } else {
                chart.draw_series(DashedLineSeries::new(points.clone(), 10, 6, style))?
            };
            series
                .label(label.as_str())
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], style));
        }
        let marker = COLOURS[0].stroke_width(2);
        chart
            .draw_series(self.data.iter().map(|&p| Circle::new(p, 4, marker)))?
            .label(self.data_label.as_str())
            .legend(move |(x, y)| Circle::new((x + 10, y), 4, marker));
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperLeft)
            .label_font(("sans-serif", 16))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .draw()?;
        Ok(())
    }
}

fn plot_error(path: &Path, e: impl std::fmt::Display) -> FitError {
    FitError::Plot {
        path: path.display().to_string(),
        message: e.to_string(),
    }
}
