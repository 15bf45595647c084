//! `usar-plot` draws the plots of the reports — a metric over time with a mean ± sd band per
//! configuration, bar charts with error bars, grouped bar charts — with `plotters`, to PNG or SVG chosen by the file
//! extension. PNG text uses DejaVu Sans embedded in the binary, so no system font is needed.
//! Files are written atomically (to memory, then [`usar_world::write_atomic`]).
//!
//! ```
//! use usar_plot::{LineChart, Series};
//! let dir = tempfile::tempdir().unwrap();
//! let chart = LineChart {
//!     title: "Coverage".into(),
//!     x_label: "time (s)".into(),
//!     y_label: "coverage".into(),
//!     series: vec![Series::line("robots", vec![(0.0, 0.0), (60.0, 0.5), (120.0, 0.9)])],
//!     y_range: Some((0.0, 1.0)),
//! };
//! chart.save(&dir.path().join("coverage.png")).unwrap();
//! chart.save(&dir.path().join("coverage.svg")).unwrap();
//! ```

mod bar;
mod font;
mod grouped;
mod line;

pub use self::bar::{Bar, BarChart};
pub use self::grouped::GroupedBarChart;
pub use self::line::{LineChart, Series};

use std::path::Path;

/// Why a plot could not be written.
#[derive(Debug, thiserror::Error)]
pub enum PlotError {
    /// The file extension is not `.png` or `.svg`.
    #[error("{path}: unsupported plot format, expected a .png or .svg file name")]
    Format { path: String },
    /// Drawing failed.
    #[error("{path}: cannot draw the plot: {message}")]
    Draw { path: String, message: String },
    /// The file could not be written.
    #[error(transparent)]
    Write(#[from] usar_world::WorldError),
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Format {
    Png,
    Svg,
}

fn format_of(path: &Path) -> Result<Format, PlotError> {
    match usar_world::io::extension(path).as_str() {
        "png" => Ok(Format::Png),
        "svg" => Ok(Format::Svg),
        _ => Err(PlotError::Format {
            path: path.display().to_string(),
        }),
    }
}

/// Colours for successive series (Tableau 10, colour-blind friendly ordering).
pub const PALETTE: [(u8, u8, u8); 8] = [
    (31, 119, 180),
    (255, 127, 14),
    (44, 160, 44),
    (214, 39, 40),
    (148, 103, 189),
    (140, 86, 75),
    (227, 119, 194),
    (127, 127, 127),
];

/// The colour of series `k` (the palette repeats).
pub(crate) fn colour(k: usize) -> plotters::style::RGBColor {
    let (r, g, b) = PALETTE[k % PALETTE.len()];
    plotters::style::RGBColor(r, g, b)
}

pub(crate) const WIDTH: u32 = 960;
pub(crate) const HEIGHT: u32 = 600;

/// A chart with two f64 axes.
pub(crate) type Chart<'a, DB> = plotters::chart::ChartContext<
    'a,
    DB,
    plotters::coord::cartesian::Cartesian2d<
        plotters::coord::types::RangedCoordf64,
        plotters::coord::types::RangedCoordf64,
    >,
>;

/// The frame every chart shares: a white page, the caption, the margins and axis areas, and
/// two f64 axes over `x` and `y`.
pub(crate) fn frame<'a, DB: plotters::prelude::DrawingBackend>(
    area: &'a plotters::drawing::DrawingArea<DB, plotters::coord::Shift>,
    title: &str,
    x: std::ops::Range<f64>,
    y: std::ops::Range<f64>,
    x_label_area: u32,
) -> Result<Chart<'a, DB>, String> {
    use plotters::prelude::*;
    area.fill(&WHITE).map_err(|e| e.to_string())?;
    ChartBuilder::on(area)
        .caption(title, ("sans-serif", 24))
        .margin(16)
        .margin_right(40)
        .x_label_area_size(x_label_area)
        .y_label_area_size(72)
        .build_cartesian_2d(x, y)
        .map_err(|e| e.to_string())
}

/// The legend box of the labelled series, at `position`.
pub(crate) fn legend<'a, DB: plotters::prelude::DrawingBackend + 'a>(
    chart: &mut Chart<'a, DB>,
    position: plotters::chart::SeriesLabelPosition,
) -> Result<(), String> {
    use plotters::prelude::*;
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font(("sans-serif", 14))
        .position(position)
        .draw()
        .map_err(|e| e.to_string())
}

/// Something drawable on any plotters backend.
pub(crate) trait Drawable {
    fn draw<DB: plotters::prelude::DrawingBackend>(
        &self,
        area: &plotters::drawing::DrawingArea<DB, plotters::coord::Shift>,
    ) -> Result<(), String>;
}

/// Renders `plot` to PNG or SVG (by extension) and writes the file atomically.
pub(crate) fn render(path: &Path, plot: &impl Drawable) -> Result<(), PlotError> {
    use plotters::drawing::IntoDrawingArea;
    let fail = |message: String| PlotError::Draw {
        path: path.display().to_string(),
        message,
    };
    // Both backends measure text with the font (SVG to place labels and legends).
    font::ensure_registered();
    match format_of(path)? {
        Format::Png => {
            let mut buf = vec![0u8; (WIDTH * HEIGHT * 3) as usize];
            {
                let area = plotters::backend::BitMapBackend::with_buffer(&mut buf, (WIDTH, HEIGHT))
                    .into_drawing_area();
                plot.draw(&area).map_err(fail)?;
                area.present().map_err(|e| fail(e.to_string()))?;
            }
            let img = image::RgbImage::from_raw(WIDTH, HEIGHT, buf)
                .ok_or_else(|| fail("buffer size".into()))?;
            let mut png = std::io::Cursor::new(Vec::new());
            img.write_to(&mut png, image::ImageFormat::Png)
                .map_err(|e| fail(e.to_string()))?;
            usar_world::write_atomic(path, png.get_ref())?;
        }
        Format::Svg => {
            let mut text = String::new();
            {
                let area = plotters::backend::SVGBackend::with_string(&mut text, (WIDTH, HEIGHT))
                    .into_drawing_area();
                plot.draw(&area).map_err(fail)?;
                area.present().map_err(|e| fail(e.to_string()))?;
            }
            usar_world::write_atomic(path, text.as_bytes())?;
        }
    }
    Ok(())
}

/// The README's examples, compiled and run as doctests.
#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;
