//! Bar charts with error bars (mean ± sd per configuration).

use crate::{Drawable, PlotError};
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use std::path::Path;

#[derive(Clone, Debug, PartialEq)]
pub struct Bar {
    pub label: String,
    pub value: f64,
    /// Half-height of the error bar (e.g. one standard deviation).
    pub error: f64,
}

#[derive(Clone, Debug, PartialEq)]
pub struct BarChart {
    pub title: String,
    pub y_label: String,
    pub bars: Vec<Bar>,
}

impl BarChart {
    pub fn save(&self, path: &Path) -> Result<(), PlotError> {
        crate::render(path, self)
    }
}

impl Drawable for BarChart {
    fn draw<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, plotters::coord::Shift>,
    ) -> Result<(), String> {
        let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
        let top = self
            .bars
            .iter()
            .map(|b| b.value + b.error.max(0.0))
            .fold(0.0f64, f64::max);
        let bottom = self
            .bars
            .iter()
            .map(|b| b.value - b.error.max(0.0))
            .fold(0.0f64, f64::min);
        let span = (top - bottom).max(1e-9);
        let n = self.bars.len().max(1);
        let mut chart = crate::frame(
            area,
            &self.title,
            0f64..n as f64,
            bottom..top + 0.12 * span,
            16,
        )?;
        chart
            .configure_mesh()
            .disable_x_mesh()
            .x_labels(0)
            .y_desc(&self.y_label)
            .label_style(("sans-serif", 14))
            .draw()
            .map_err(e)?;
        let label_style = TextStyle::from(("sans-serif", 15).into_font())
            .pos(Pos::new(HPos::Center, VPos::Bottom));
        for (k, b) in self.bars.iter().enumerate() {
            let x = k as f64;
            let (lo, hi) = (b.value - b.error, b.value + b.error);
            let mid = x + 0.5;
            chart
                .draw_series(std::iter::once(Rectangle::new(
                    [(x + 0.15, 0.0), (x + 0.85, b.value)],
                    crate::colour(k).filled(),
                )))
                .map_err(e)?;
            chart
                .draw_series([
                    PathElement::new(vec![(mid, lo), (mid, hi)], BLACK.stroke_width(2)),
                    PathElement::new(
                        vec![(mid - 0.08, lo), (mid + 0.08, lo)],
                        BLACK.stroke_width(2),
                    ),
                    PathElement::new(
                        vec![(mid - 0.08, hi), (mid + 0.08, hi)],
                        BLACK.stroke_width(2),
                    ),
                ])
                .map_err(e)?;
            chart
                .draw_series(std::iter::once(Text::new(
                    b.label.clone(),
                    (mid, hi.max(b.value) + 0.02 * span),
                    label_style.clone(),
                )))
                .map_err(e)?;
        }
        Ok(())
    }
}
