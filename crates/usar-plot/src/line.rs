//! A metric over time, one line per configuration, with an optional mean ± sd band.

use crate::{Drawable, PlotError};
use plotters::prelude::*;
use std::path::Path;

/// One line of a [`LineChart`].
#[derive(Clone, Debug, PartialEq)]
pub struct Series {
    pub label: String,
    /// (x, y) points, x increasing.
    pub points: Vec<(f64, f64)>,
    /// Optional standard deviation at each point: the band y ± sd is shaded.
    pub sd: Option<Vec<f64>>,
}

impl Series {
    pub fn line(label: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Self {
            label: label.into(),
            points,
            sd: None,
        }
    }

    pub fn with_band(label: impl Into<String>, points: Vec<(f64, f64)>, sd: Vec<f64>) -> Self {
        Self {
            label: label.into(),
            points,
            sd: Some(sd),
        }
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct LineChart {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub series: Vec<Series>,
    /// Fixed y range; `None` fits the data (bands included).
    pub y_range: Option<(f64, f64)>,
}

impl LineChart {
    /// Writes the chart; the format follows the extension (`.png` or `.svg`).
    pub fn save(&self, path: &Path) -> Result<(), PlotError> {
        crate::render(path, self)
    }

    fn ranges(&self) -> ((f64, f64), (f64, f64)) {
        let mut x = (f64::INFINITY, f64::NEG_INFINITY);
        let mut y = (f64::INFINITY, f64::NEG_INFINITY);
        for s in &self.series {
            for (k, &(px, py)) in s.points.iter().enumerate() {
                let sd = s.sd.as_ref().and_then(|v| v.get(k)).copied().unwrap_or(0.0);
                x = (x.0.min(px), x.1.max(px));
                y = (y.0.min(py - sd), y.1.max(py + sd));
            }
        }
        if !x.0.is_finite() {
            x = (0.0, 1.0);
            y = (0.0, 1.0);
        }
        if x.1 <= x.0 {
            x.1 = x.0 + 1.0;
        }
        if y.1 <= y.0 {
            y.1 = y.0 + 1.0;
        }
        let pad = (y.1 - y.0) * 0.05;
        (x, self.y_range.unwrap_or((y.0 - pad, y.1 + pad)))
    }
}

impl Drawable for LineChart {
    fn draw<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, plotters::coord::Shift>,
    ) -> Result<(), String> {
        let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
        let ((x0, x1), (y0, y1)) = self.ranges();
        let mut chart = crate::frame(area, &self.title, x0..x1, y0..y1, 48)?;
        chart
            .configure_mesh()
            .x_desc(&self.x_label)
            .y_desc(&self.y_label)
            .label_style(("sans-serif", 14))
            .light_line_style(RGBColor(235, 235, 235))
            .draw()
            .map_err(e)?;
        for (k, s) in self.series.iter().enumerate() {
            let colour = crate::colour(k);
            if let Some(sd) = &s.sd {
                let upper = s.points.iter().zip(sd).map(|(&(x, y), &d)| (x, y + d));
                let lower = s
                    .points
                    .iter()
                    .zip(sd)
                    .rev()
                    .map(|(&(x, y), &d)| (x, y - d));
                let band: Vec<(f64, f64)> = upper.chain(lower).collect();
                chart
                    .draw_series(std::iter::once(Polygon::new(
                        band,
                        colour.mix(0.2).filled(),
                    )))
                    .map_err(e)?;
            }
            chart
                .draw_series(LineSeries::new(
                    s.points.iter().copied(),
                    colour.stroke_width(2),
                ))
                .map_err(e)?
                .label(s.label.clone())
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(2))
                });
        }
        if self.series.iter().any(|s| !s.label.is_empty()) {
            crate::legend(&mut chart, SeriesLabelPosition::LowerRight)?;
        }
        Ok(())
    }
}
