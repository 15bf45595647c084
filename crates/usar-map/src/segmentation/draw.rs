//! A segmentation drawn over its scene.

use super::Segmentation;
use usar_world::render::Canvas;
use usar_world::{RoomLabel, Scene};

impl Segmentation {
    /// Segments in distinct colours (rooms saturated, corridors pale), walls dark, free cells
    /// outside every segment white, doors as red crosses; at most 1600 px wide or high.
    pub fn draw(&self, scene: &Scene) -> Canvas {
        let g = *scene.geometry();
        let mut canvas = Canvas::fit(g, 1600);
        canvas.fill([60, 60, 60]);
        for (i, &l) in self.room_id.as_slice().iter().enumerate() {
            let cell = g.cell_of_index(i);
            let rgb = if l == 0 {
                if scene.is_obstacle(cell) {
                    [30, 30, 30]
                } else {
                    [255, 255, 255]
                }
            } else {
                let s = &self.segments[usize::from(l) - 1];
                segment_colour(l, s.label == RoomLabel::Corridor)
            };
            canvas.fill_cell(cell, rgb);
        }
        for d in &self.doors {
            canvas.draw_cross(d.position, d.width_m.max(0.6), [220, 0, 0]);
        }
        canvas
    }
}

/// A colour per segment: hues spaced by the golden angle; corridors pale.
fn segment_colour(id: u16, corridor: bool) -> [u8; 3] {
    let hue = (f64::from(id) * 137.507_764) % 360.0;
    let (s, v) = if corridor { (0.15, 0.95) } else { (0.6, 0.9) };
    let c = v * s;
    let x = c * (1.0 - ((hue / 60.0) % 2.0 - 1.0).abs());
    let (r, g, b) = match (hue / 60.0) as u32 {
        0 => (c, x, 0.0),
        1 => (x, c, 0.0),
        2 => (0.0, c, x),
        3 => (0.0, x, c),
        4 => (x, 0.0, c),
        _ => (c, 0.0, x),
    };
    let m = v - c;
    [r, g, b].map(|u| ((u + m) * 255.0).round() as u8)
}

#[cfg(test)]
mod tests {
    use super::segment_colour;

    #[test]
    fn corridors_are_paler_than_rooms() {
        let sum = |c: [u8; 3]| c.iter().map(|&u| u32::from(u)).sum::<u32>();
        for id in 1..20 {
            assert!(sum(segment_colour(id, true)) > sum(segment_colour(id, false)));
        }
    }
}
