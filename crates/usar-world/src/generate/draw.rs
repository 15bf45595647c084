//! Small drawing helpers shared by the generators: they paint rectangles of world space into a
//! scene's layers. Rectangles cover the cells whose centres lie inside them.

use crate::geometry::Rect;
use crate::grid::{Cell, Grid, GridGeometry};
use crate::scene::{RoomId, Scene};

/// The cells whose centres lie inside `rect`, clipped to the grid.
pub fn cells_in_rect(g: &GridGeometry, rect: Rect) -> impl Iterator<Item = Cell> + use<> {
    let r = g.resolution_m;
    let c0 = (((rect.min.x - g.origin.x) / r - 0.5).ceil() as i32).max(0);
    let r0 = (((rect.min.y - g.origin.y) / r - 0.5).ceil() as i32).max(0);
    let c1 = (((rect.max.x - g.origin.x) / r - 0.5).floor() as i32).min(g.width as i32 - 1);
    let r1 = (((rect.max.y - g.origin.y) / r - 0.5).floor() as i32).min(g.height as i32 - 1);
    (r0..=r1).flat_map(move |row| (c0..=c1).map(move |col| Cell::new(col, row)))
}

/// Sets every cell of `grid` inside `rect` to `value`.
pub fn fill_rect<T: Copy>(grid: &mut Grid<T>, rect: Rect, value: T) {
    let g = *grid.geometry();
    for c in cells_in_rect(&g, rect) {
        grid[c] = value;
    }
}

/// Marks `rect` as an obstacle of the given kind (see [`crate::scene::obstacle`]).
pub fn fill_obstacle(scene: &mut Scene, rect: Rect, kind: u8) {
    fill_rect(&mut scene.obstacle, rect, kind);
}

/// Assigns the cells of `rect` to room `id`.
pub fn fill_room(scene: &mut Scene, rect: Rect, id: RoomId) {
    fill_rect(&mut scene.room_id, rect, id);
}

/// Sets the floor height of every cell in `rect` from a function of the cell centre.
pub fn shape_floor(scene: &mut Scene, rect: Rect, mut height_m: impl FnMut(crate::Point2) -> f32) {
    let g = *scene.geometry();
    for c in cells_in_rect(&g, rect) {
        scene.floor_height_m[c] = height_m(g.cell_center(c));
    }
}

/// Draws the outline of `rect` as walls `thickness_m` thick (inside the rectangle).
pub fn wall_outline(scene: &mut Scene, rect: Rect, thickness_m: f64) {
    let t = thickness_m;
    let (a, b) = (rect.min, rect.max);
    for side in [
        Rect::new(a.x, a.y, b.x, a.y + t),
        Rect::new(a.x, b.y - t, b.x, b.y),
        Rect::new(a.x, a.y, a.x + t, b.y),
        Rect::new(b.x - t, a.y, b.x, b.y),
    ] {
        fill_obstacle(scene, side, crate::scene::obstacle::WALL);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Point2;

    #[test]
    fn cells_in_rect_takes_cells_whose_centres_are_inside() {
        let g = GridGeometry::new(10, 10, 0.1, Point2::new(0.0, 0.0));
        let cells: Vec<_> = cells_in_rect(&g, Rect::new(0.1, 0.1, 0.3, 0.2)).collect();
        assert_eq!(cells, vec![Cell::new(1, 1), Cell::new(2, 1)]);
        assert_eq!(
            cells_in_rect(&g, Rect::new(-5.0, -5.0, 50.0, 50.0)).count(),
            100
        );
    }
}
