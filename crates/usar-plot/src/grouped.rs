//! Grouped bar charts: for every group (e.g. a participant) one bar per series (e.g. a control
//! mode), side by side, with a legend — the layout of paper 000's Fig. 16–18.

use crate::{Drawable, PlotError};
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use std::path::Path;

#[derive(Clone, Debug, PartialEq)]
pub struct GroupedBarChart {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    /// The group labels along the x axis.
    pub groups: Vec<String>,
    /// Named series; each holds one value per group (missing values are not drawn).
    pub series: Vec<(String, Vec<f64>)>,
}

impl GroupedBarChart {
    pub fn save(&self, path: &Path) -> Result<(), PlotError> {
        crate::render(path, self)
    }
}

impl Drawable for GroupedBarChart {
    fn draw<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, plotters::coord::Shift>,
    ) -> Result<(), String> {
        let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
        let values = self.series.iter().flat_map(|(_, v)| v.iter().copied());
        let top = values.clone().fold(0.0f64, f64::max);
        let bottom = values.fold(0.0f64, f64::min);
        let span = (top - bottom).max(1e-9);
        let n = self.groups.len().max(1);
        let mut chart = crate::frame(
            area,
            &self.title,
            0f64..n as f64,
            bottom..top + 0.15 * span,
            48,
        )?;
        chart
            .configure_mesh()
            .disable_x_mesh()
            .x_labels(0)
            .x_desc(&self.x_label)
            .y_desc(&self.y_label)
            .label_style(("sans-serif", 14))
            .draw()
            .map_err(e)?;
        let m = self.series.len().max(1) as f64;
        let width = 0.8 / m;
        for (s, (name, values)) in self.series.iter().enumerate() {
            let color = crate::colour(s);
            let left = |k: usize| k as f64 + 0.1 + s as f64 * width;
            chart
                .draw_series(
                    values
                        .iter()
                        .enumerate()
                        .filter(|(_, v)| v.is_finite())
                        .map(|(k, &v)| {
                            Rectangle::new([(left(k), 0.0), (left(k) + width, v)], color.filled())
                        }),
                )
                .map_err(e)?
                .label(name.clone())
                .legend(move |(x, y)| {
                    Rectangle::new([(x, y - 5), (x + 12, y + 5)], color.filled())
                });
        }
        // Group labels centred under their bars (the axis' own ticks fall between groups).
        let label_style =
            TextStyle::from(("sans-serif", 14).into_font()).pos(Pos::new(HPos::Center, VPos::Top));
        for (k, label) in self.groups.iter().enumerate() {
            let (x, y) = chart.backend_coord(&(k as f64 + 0.5, bottom));
            area.draw(&Text::new(label.clone(), (x, y + 6), label_style.clone()))
                .map_err(e)?;
        }
        crate::legend(&mut chart, SeriesLabelPosition::UpperRight)
    }
}
