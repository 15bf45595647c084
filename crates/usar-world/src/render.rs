//! Raster pictures of grids and scenes: the [`Canvas`] every crate draws maps on, and
//! [`render_scene`], the ground-truth picture of a [`Scene`].
//!
//! A canvas covers one [`GridGeometry`] and draws in world coordinates (metres, y up). Image row 0
//! is the top of the picture, i.e. the northernmost part of the grid; that flip happens inside the
//! canvas and nowhere else. A canvas either magnifies (`px_per_cell` ≥ 1 pixels per cell side) or,
//! for grids larger than the requested picture, downsamples (`cells_per_px` ≥ 2 cells per pixel
//! side); when several cells share a pixel, the cell painted last wins, so painters draw what must
//! stay visible (walls) last.
//!
//! There is no text rendering here: legends belong to the plotting crate.

use crate::error::{Result, WorldError};
use crate::geometry::{Point2, Pose2};
use crate::grid::{Cell, GridGeometry};
use crate::scene::{RoomLabel, Scene, TerrainFeature, obstacle};
use std::path::Path;

/// Largest side of a canvas, pixels. Larger requests are scaled down to it, so a huge
/// `px_per_cell` from a command line never allocates gigabytes.
pub const MAX_CANVAS_SIDE_PX: u32 = 16_384;

/// The colours of [`render_scene`].
///
/// | what | colour |
/// |---|---|
/// | flat floor (height within ±[`FLAT_TOLERANCE_M`]) | white |
/// | raised floor (rubble, slopes, stairs) | pale sand → ochre → dark brown at `height_full_scale_m` |
/// | lowered floor (drops, pits) | pale blue → dark blue at −`height_full_scale_m` |
/// | corridor / small / medium / big room | light tint of teal / green / purple / amber |
/// | wall / furniture | black / dark grey |
/// | door | dark green across the doorway |
/// | victim in the open / partly buried / mostly buried | red disc / darker red disc / dark red ring |
/// | heat source that is not a victim | orange disc |
/// | start pose | blue triangle pointing along the heading |
/// | ground-truth junction / terrain feature | magenta cross / cyan outline |
///
/// [`FLAT_TOLERANCE_M`]: crate::render::FLAT_TOLERANCE_M
pub mod palette {
    pub const FLOOR: [u8; 3] = [255, 255, 255];
    pub const WALL: [u8; 3] = [0, 0, 0];
    pub const FURNITURE: [u8; 3] = [90, 90, 90];
    /// Raised floor, from just above flat to full scale.
    pub const RAISED: [[u8; 3]; 3] = [[238, 226, 196], [214, 165, 96], [122, 72, 32]];
    /// Lowered floor, from just below flat to full scale.
    pub const LOWERED: [[u8; 3]; 2] = [[208, 226, 245], [30, 60, 150]];
    pub const CORRIDOR: [u8; 3] = [0, 150, 136];
    pub const SMALL_ROOM: [u8; 3] = [76, 175, 80];
    pub const MEDIUM_ROOM: [u8; 3] = [156, 39, 176];
    pub const BIG_ROOM: [u8; 3] = [255, 152, 0];
    /// Share of the label colour in a room tint.
    pub const LABEL_TINT_ALPHA: f32 = 0.25;
    pub const DOOR: [u8; 3] = [0, 120, 0];
    pub const VICTIM: [u8; 3] = [220, 0, 0];
    pub const VICTIM_BURIED: [u8; 3] = [120, 0, 0];
    pub const HEAT_SOURCE: [u8; 3] = [255, 140, 0];
    pub const START_POSE: [u8; 3] = [25, 80, 230];
    pub const JUNCTION: [u8; 3] = [200, 0, 200];
    pub const TERRAIN_FEATURE: [u8; 3] = [0, 170, 200];
}

/// Floor heights within ± this many metres of 0 are drawn as flat floor.
pub const FLAT_TOLERANCE_M: f32 = 0.005;

/// A raster image over a grid geometry, drawn in world coordinates.
#[derive(Clone, Debug, PartialEq)]
pub struct Canvas {
    geometry: GridGeometry,
    px_per_cell: u32,
    cells_per_px: u32,
    width: u32,
    height: u32,
    /// RGB, row-major, row 0 at the top.
    rgb: Vec<u8>,
}

impl Canvas {
    /// A white canvas with `px_per_cell` pixels per cell side (at least 1; reduced, or turned
    /// into downsampling, when the picture would exceed [`MAX_CANVAS_SIDE_PX`]).
    pub fn new(geometry: GridGeometry, px_per_cell: u32) -> Self {
        let larger = geometry.width.max(geometry.height).max(1);
        if larger > MAX_CANVAS_SIDE_PX {
            return Self::fit(geometry, MAX_CANVAS_SIDE_PX);
        }
        let px = px_per_cell.clamp(1, MAX_CANVAS_SIDE_PX / larger);
        Self::with_scale(geometry, px, 1)
    }

    /// The largest canvas whose larger side is at most `max_side_px` (clamped to
    /// 1..=[`MAX_CANVAS_SIDE_PX`]): the largest whole `px_per_cell` ≥ 1 when the grid fits, else
    /// downsampling by the smallest whole `cells_per_px` that fits.
    pub fn fit(geometry: GridGeometry, max_side_px: u32) -> Self {
        let max_side = max_side_px.clamp(1, MAX_CANVAS_SIDE_PX);
        let larger = geometry.width.max(geometry.height).max(1);
        if larger <= max_side {
            Self::with_scale(geometry, max_side / larger, 1)
        } else {
            Self::with_scale(geometry, 1, larger.div_ceil(max_side))
        }
    }

    fn with_scale(geometry: GridGeometry, px_per_cell: u32, cells_per_px: u32) -> Self {
        let side = |cells: u32| (cells * px_per_cell).div_ceil(cells_per_px);
        let (width, height) = (side(geometry.width), side(geometry.height));
        let rgb = vec![255; width as usize * height as usize * 3];
        Self {
            geometry,
            px_per_cell,
            cells_per_px,
            width,
            height,
            rgb,
        }
    }

    pub fn width(&self) -> u32 {
        self.width
    }

    pub fn height(&self) -> u32 {
        self.height
    }

    pub fn geometry(&self) -> &GridGeometry {
        &self.geometry
    }

    /// Pixels per cell side (1 when downsampling).
    pub fn px_per_cell(&self) -> u32 {
        self.px_per_cell
    }

    /// Cells per pixel side (1 when magnifying).
    pub fn cells_per_px(&self) -> u32 {
        self.cells_per_px
    }

    /// Pixels per metre.
    pub fn px_per_m(&self) -> f64 {
        f64::from(self.px_per_cell) / (f64::from(self.cells_per_px) * self.geometry.resolution_m)
    }

    /// The RGB bytes, row-major from the top row.
    pub fn as_rgb_bytes(&self) -> &[u8] {
        &self.rgb
    }

    /// The colour of pixel (x, y), y counted down from the top; `None` outside.
    pub fn pixel(&self, x: u32, y: u32) -> Option<[u8; 3]> {
        (x < self.width && y < self.height).then(|| {
            let i = (y as usize * self.width as usize + x as usize) * 3;
            [self.rgb[i], self.rgb[i + 1], self.rgb[i + 2]]
        })
    }

    /// Sets pixel (x, y); pixels outside the canvas are ignored.
    #[inline]
    pub fn set_pixel(&mut self, x: i64, y: i64, rgb: [u8; 3]) {
        if x >= 0 && y >= 0 && x < i64::from(self.width) && y < i64::from(self.height) {
            let i = (y as usize * self.width as usize + x as usize) * 3;
            self.rgb[i..i + 3].copy_from_slice(&rgb);
        }
    }

    /// Paints the whole canvas.
    pub fn fill(&mut self, rgb: [u8; 3]) {
        for px in self.rgb.chunks_exact_mut(3) {
            px.copy_from_slice(&rgb);
        }
    }

    /// The pixel rectangle `(x0, y0, x1, y1)` (exclusive ends) a cell covers; `None` outside the
    /// grid. When downsampling it is the one pixel the cell falls in.
    pub fn cell_pixels(&self, cell: Cell) -> Option<(u32, u32, u32, u32)> {
        if !self.geometry.contains(cell) {
            return None;
        }
        let (col, row) = (cell.col as u32, cell.row as u32);
        if self.cells_per_px > 1 {
            let (x, y) = (
                col / self.cells_per_px,
                self.height - 1 - row / self.cells_per_px,
            );
            return Some((x, y, x + 1, y + 1));
        }
        let p = self.px_per_cell;
        let y1 = self.height - row * p;
        Some((col * p, y1 - p, col * p + p, y1))
    }

    /// Paints a cell (ignored outside the grid).
    #[inline]
    pub fn fill_cell(&mut self, cell: Cell, rgb: [u8; 3]) {
        if let Some((x0, y0, x1, y1)) = self.cell_pixels(cell) {
            let w = self.width as usize;
            for y in y0 as usize..y1 as usize {
                for px in self.rgb[(y * w + x0 as usize) * 3..(y * w + x1 as usize) * 3]
                    .chunks_exact_mut(3)
                {
                    px.copy_from_slice(&rgb);
                }
            }
        }
    }

    /// Blends `rgb` over a cell with opacity `alpha` (clamped to [0, 1]; NaN counts as 0).
    pub fn blend_cell(&mut self, cell: Cell, rgb: [u8; 3], alpha: f32) {
        let a = if alpha.is_nan() {
            0
        } else {
            (alpha.clamp(0.0, 1.0) * 255.0).round() as u32
        };
        if let Some((x0, y0, x1, y1)) = self.cell_pixels(cell) {
            let w = self.width as usize;
            for y in y0 as usize..y1 as usize {
                for px in self.rgb[(y * w + x0 as usize) * 3..(y * w + x1 as usize) * 3]
                    .chunks_exact_mut(3)
                {
                    for (old, new) in px.iter_mut().zip(rgb) {
                        *old = blend_channel(*old, new, a);
                    }
                }
            }
        }
    }

    /// A world point in continuous pixel coordinates (x right, y down from the top edge).
    pub fn to_px(&self, p: Point2) -> (f64, f64) {
        let s = self.px_per_m();
        let x = (p.x - self.geometry.origin.x) * s;
        let y = f64::from(self.height) - (p.y - self.geometry.origin.y) * s;
        (x, y)
    }

    /// The pixel containing a continuous pixel position, with the same half-open convention as
    /// [`GridGeometry::world_to_cell`] (a cell's lower and left edges belong to it).
    fn containing(x: f64, y: f64) -> (i64, i64) {
        (x.floor() as i64, y.ceil() as i64 - 1)
    }

    /// Fills the pixels whose centres lie within `radius_m` of `center` (at least the pixel
    /// containing `center`).
    pub fn draw_disc(&mut self, center: Point2, radius_m: f64, rgb: [u8; 3]) {
        self.draw_ring(center, radius_m, None, rgb);
    }

    /// Draws a one-pixel circle of radius `radius_m` around `center` (the centre pixel when the
    /// circle is smaller than a pixel).
    pub fn draw_circle(&mut self, center: Point2, radius_m: f64, rgb: [u8; 3]) {
        let r = radius_m * self.px_per_m();
        self.draw_ring(center, radius_m, Some((r - 0.5).max(0.0)), rgb);
    }

    /// Pixels whose centres are at distance d from `center` with `inner_px ≤ d ≤ radius`.
    fn draw_ring(&mut self, center: Point2, radius_m: f64, inner_px: Option<f64>, rgb: [u8; 3]) {
        let (cx, cy) = self.to_px(center);
        let r_px = radius_m * self.px_per_m();
        if !(cx.is_finite() && cy.is_finite() && r_px.is_finite()) {
            return;
        }
        let (ix, iy) = Self::containing(cx, cy);
        let outer = if inner_px.is_some() { r_px + 0.5 } else { r_px };
        if inner_px.is_none() || outer < 0.5 {
            self.set_pixel(ix, iy, rgb);
        }
        if outer < 0.5 {
            return;
        }
        let (outer2, inner2) = (outer * outer, inner_px.map_or(-1.0, |i| i * i));
        let clamp_x = |v: f64| v.clamp(0.0, f64::from(self.width)) as i64;
        let clamp_y = |v: f64| v.clamp(0.0, f64::from(self.height)) as i64;
        let (x0, x1) = (clamp_x((cx - outer).floor()), clamp_x((cx + outer).ceil()));
        let (y0, y1) = (clamp_y((cy - outer).floor()), clamp_y((cy + outer).ceil()));
        for y in y0..y1 {
            let dy = y as f64 + 0.5 - cy;
            for x in x0..x1 {
                let dx = x as f64 + 0.5 - cx;
                let d2 = dx * dx + dy * dy;
                if d2 <= outer2 && d2 >= inner2 {
                    self.set_pixel(x, y, rgb);
                }
            }
        }
    }

    /// Draws a one-pixel line from `a` to `b` (clipped to the canvas).
    pub fn draw_line(&mut self, a: Point2, b: Point2, rgb: [u8; 3]) {
        let (ax, ay) = self.to_px(a);
        let (bx, by) = self.to_px(b);
        let bounds = (
            -1.0,
            -1.0,
            f64::from(self.width) + 1.0,
            f64::from(self.height) + 1.0,
        );
        let Some((ax, ay, bx, by)) = clip_segment(ax, ay, bx, by, bounds) else {
            return;
        };
        let steps = (bx - ax).abs().max((by - ay).abs()).ceil().max(1.0) as i64;
        for i in 0..=steps {
            let t = i as f64 / steps as f64;
            let (x, y) = Self::containing(ax + (bx - ax) * t, ay + (by - ay) * t);
            self.set_pixel(x, y, rgb);
        }
    }

    /// Draws lines between consecutive points.
    pub fn draw_polyline(&mut self, points: &[Point2], rgb: [u8; 3]) {
        for pair in points.windows(2) {
            self.draw_line(pair[0], pair[1], rgb);
        }
        if let [only] = points {
            self.draw_line(*only, *only, rgb);
        }
    }

    /// Draws a pose as a filled triangle `size_m` long pointing along the heading (tip 0.6 of the
    /// size ahead of the position, base 0.4 behind it, 0.8 wide).
    pub fn draw_pose(&mut self, pose: Pose2, size_m: f64, rgb: [u8; 3]) {
        let corners = [
            pose.to_world(Point2::new(0.6 * size_m, 0.0)),
            pose.to_world(Point2::new(-0.4 * size_m, 0.4 * size_m)),
            pose.to_world(Point2::new(-0.4 * size_m, -0.4 * size_m)),
        ];
        let [a, b, c] = corners.map(|p| self.to_px(p));
        if [a, b, c]
            .iter()
            .any(|(x, y)| !(x.is_finite() && y.is_finite()))
        {
            return;
        }
        let clamp_x = |v: f64| v.clamp(0.0, f64::from(self.width)) as i64;
        let clamp_y = |v: f64| v.clamp(0.0, f64::from(self.height)) as i64;
        let (x0, x1) = (
            clamp_x(a.0.min(b.0).min(c.0).floor()),
            clamp_x(a.0.max(b.0).max(c.0).ceil()),
        );
        let (y0, y1) = (
            clamp_y(a.1.min(b.1).min(c.1).floor()),
            clamp_y(a.1.max(b.1).max(c.1).ceil()),
        );
        let edge = |p: (f64, f64), q: (f64, f64), x: f64, y: f64| {
            (q.0 - p.0) * (y - p.1) - (q.1 - p.1) * (x - p.0)
        };
        for y in y0..y1 {
            let py = y as f64 + 0.5;
            for x in x0..x1 {
                let px = x as f64 + 0.5;
                let (e0, e1, e2) = (edge(a, b, px, py), edge(b, c, px, py), edge(c, a, px, py));
                let inside =
                    (e0 >= 0.0 && e1 >= 0.0 && e2 >= 0.0) || (e0 <= 0.0 && e1 <= 0.0 && e2 <= 0.0);
                if inside {
                    self.set_pixel(x, y, rgb);
                }
            }
        }
        self.draw_polyline(&[corners[0], corners[1], corners[2], corners[0]], rgb);
        let (ix, iy) = self.to_px(pose.position());
        let (ix, iy) = Self::containing(ix, iy);
        self.set_pixel(ix, iy, rgb);
    }

    /// Draws an × of side `size_m` centred on `p`.
    pub fn draw_cross(&mut self, p: Point2, size_m: f64, rgb: [u8; 3]) {
        let h = size_m / 2.0;
        self.draw_line(
            Point2::new(p.x - h, p.y - h),
            Point2::new(p.x + h, p.y + h),
            rgb,
        );
        self.draw_line(
            Point2::new(p.x - h, p.y + h),
            Point2::new(p.x + h, p.y - h),
            rgb,
        );
    }

    /// The picture as an `image` buffer.
    pub fn into_image(self) -> image::RgbImage {
        image::RgbImage::from_raw(self.width, self.height, self.rgb).expect("3 bytes per pixel")
    }

    /// Encodes the canvas as PNG.
    pub fn encode_png(&self) -> std::result::Result<Vec<u8>, image::ImageError> {
        use image::ImageEncoder as _;
        let mut bytes = Vec::new();
        image::codecs::png::PngEncoder::new(&mut bytes).write_image(
            &self.rgb,
            self.width,
            self.height,
            image::ExtendedColorType::Rgb8,
        )?;
        Ok(bytes)
    }

    /// Writes the canvas as a PNG file (encoded in memory, then written atomically).
    pub fn save_png(&self, path: &Path) -> Result<()> {
        let bytes = self.encode_png().map_err(|e| WorldError::Image {
            path: path.display().to_string(),
            message: e.to_string(),
        })?;
        crate::atomic::write_atomic(path, &bytes)
    }
}

/// `old·(1 − a) + new·a` with a in 0..=255, rounded.
#[inline]
fn blend_channel(old: u8, new: u8, a: u32) -> u8 {
    ((u32::from(old) * (255 - a) + u32::from(new) * a + 127) / 255) as u8
}

/// Mixes two colours, `t` = 0 gives `a`, 1 gives `b`.
fn mix(a: [u8; 3], b: [u8; 3], t: f32) -> [u8; 3] {
    let t = t.clamp(0.0, 1.0);
    [0, 1, 2].map(|i| (f32::from(a[i]) + (f32::from(b[i]) - f32::from(a[i])) * t).round() as u8)
}

/// Liang–Barsky clipping of a segment to `(xmin, ymin, xmax, ymax)`.
fn clip_segment(
    ax: f64,
    ay: f64,
    bx: f64,
    by: f64,
    (xmin, ymin, xmax, ymax): (f64, f64, f64, f64),
) -> Option<(f64, f64, f64, f64)> {
    if ![ax, ay, bx, by].iter().all(|v| v.is_finite()) {
        return None;
    }
    let (dx, dy) = (bx - ax, by - ay);
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (p, q) in [
        (-dx, ax - xmin),
        (dx, xmax - ax),
        (-dy, ay - ymin),
        (dy, ymax - ay),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
        } else {
            let r = q / p;
            if p < 0.0 {
                t0 = t0.max(r);
            } else {
                t1 = t1.min(r);
            }
        }
    }
    (t0 <= t1).then_some((ax + t0 * dx, ay + t0 * dy, ax + t1 * dx, ay + t1 * dy))
}

/// What [`render_scene`] draws and how large.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RenderOptions {
    /// Pixels per cell side; `None` fits the picture into `max_side_px`.
    pub px_per_cell: Option<u32>,
    /// Largest picture side when `px_per_cell` is `None` (default 1600).
    pub max_side_px: u32,
    /// Room tints and doors (default on).
    pub show_labels: bool,
    /// Floor shaded by height (default on); otherwise all floor is white.
    pub show_heights: bool,
    /// Victims and heat sources (default on).
    pub show_victims: bool,
    /// Ground-truth junctions (crosses) and terrain-feature outlines (default off).
    pub show_ground_truth: bool,
    /// Height whose colour is the darkest of the ramp (and −this for drops), metres; default 1 m,
    /// about the tallest rubble pile of paper 000 that a crawler still meets.
    pub height_full_scale_m: f32,
}

impl Default for RenderOptions {
    fn default() -> Self {
        Self {
            px_per_cell: None,
            max_side_px: 1600,
            show_labels: true,
            show_heights: true,
            show_victims: true,
            show_ground_truth: false,
            height_full_scale_m: 1.0,
        }
    }
}

/// The colour of open floor at `height_m` (see [`palette`]).
pub fn floor_colour(height_m: f32, full_scale_m: f32) -> [u8; 3] {
    if !height_m.is_finite() || height_m.abs() <= FLAT_TOLERANCE_M {
        return palette::FLOOR;
    }
    let full = if full_scale_m.is_finite() && full_scale_m > 0.0 {
        full_scale_m
    } else {
        1.0
    };
    let t = (height_m.abs() / full).min(1.0);
    if height_m > 0.0 {
        let [low, mid, high] = palette::RAISED;
        if t < 0.5 {
            mix(low, mid, t * 2.0)
        } else {
            mix(mid, high, (t - 0.5) * 2.0)
        }
    } else {
        mix(palette::LOWERED[0], palette::LOWERED[1], t)
    }
}

/// The tint colour of a room label (see [`palette`]).
pub fn label_colour(label: RoomLabel) -> [u8; 3] {
    match label {
        RoomLabel::Corridor => palette::CORRIDOR,
        RoomLabel::SmallRoom => palette::SMALL_ROOM,
        RoomLabel::MediumRoom => palette::MEDIUM_ROOM,
        RoomLabel::BigRoom => palette::BIG_ROOM,
    }
}

/// The ground-truth picture of a scene (colours in [`palette`]).
///
/// Floor first (height ramp, room tints), then furniture, then walls, so that thin walls stay
/// visible when the canvas downsamples; then doors, victims, heat sources, start poses and, if
/// asked, ground truth. Marks are at least a few pixels large whatever the scale.
pub fn render_scene(scene: &Scene, opts: &RenderOptions) -> Canvas {
    let g = *scene.geometry();
    let mut canvas = match opts.px_per_cell {
        Some(px) => Canvas::new(g, px),
        None => Canvas::fit(g, opts.max_side_px),
    };
    let min_mark_m = 1.0 / canvas.px_per_m();
    paint_cells(&mut canvas, scene, opts);
    if opts.show_labels {
        for door in &scene.doors {
            paint_door(&mut canvas, scene, door.position, door.width_m);
        }
    }
    if opts.show_ground_truth {
        for feature in &scene.ground_truth.features {
            let region = match feature {
                TerrainFeature::Hall { region }
                | TerrainFeature::Slope { region, .. }
                | TerrainFeature::Stairs { region, .. }
                | TerrainFeature::Rubble { region, .. }
                | TerrainFeature::Drop { region, .. } => region,
            };
            let (a, b) = (region.min, region.max);
            let corners = [a, Point2::new(b.x, a.y), b, Point2::new(a.x, b.y), a];
            canvas.draw_polyline(&corners, palette::TERRAIN_FEATURE);
        }
    }
    if opts.show_victims {
        for h in &scene.heat_sources {
            let r = (h.size_m2.max(0.0) / std::f64::consts::PI)
                .sqrt()
                .max(3.0 * min_mark_m);
            canvas.draw_disc(h.position, r, palette::HEAT_SOURCE);
        }
        for v in &scene.victims {
            let r = (v.visible_size_m2.max(0.0) / std::f64::consts::PI)
                .sqrt()
                .max(3.0 * min_mark_m);
            let buried = v.buried_fraction.clamp(0.0, 1.0) as f32;
            if buried >= 0.5 {
                canvas.draw_circle(v.position, r, palette::VICTIM_BURIED);
                canvas.draw_circle(
                    v.position,
                    (r - min_mark_m).max(0.0),
                    palette::VICTIM_BURIED,
                );
            } else {
                canvas.draw_disc(
                    v.position,
                    r,
                    mix(palette::VICTIM, palette::VICTIM_BURIED, buried * 2.0),
                );
            }
        }
    }
    for pose in &scene.start_poses {
        canvas.draw_pose(*pose, 0.6f64.max(10.0 * min_mark_m), palette::START_POSE);
    }
    if opts.show_ground_truth {
        for j in &scene.ground_truth.junctions {
            canvas.draw_cross(j.position, 0.3f64.max(7.0 * min_mark_m), palette::JUNCTION);
        }
    }
    canvas
}

/// Floor, furniture and walls, in that order.
fn paint_cells(canvas: &mut Canvas, scene: &Scene, opts: &RenderOptions) {
    let g = *scene.geometry();
    let max_room = scene.rooms.iter().map(|r| r.id).max().unwrap_or(0) as usize;
    let mut tint_of_room: Vec<Option<[u8; 3]>> = vec![None; max_room + 1];
    if opts.show_labels {
        for room in &scene.rooms {
            tint_of_room[room.id as usize] = Some(label_colour(room.label));
        }
    }
    let alpha = (palette::LABEL_TINT_ALPHA * 255.0).round() as u32;
    let obstacles = scene.obstacle.as_slice();
    let heights = scene.floor_height_m.as_slice();
    let rooms = scene.room_id.as_slice();
    for (i, &o) in obstacles.iter().enumerate() {
        if o != obstacle::NONE {
            continue;
        }
        let mut colour = if opts.show_heights {
            floor_colour(heights[i], opts.height_full_scale_m)
        } else {
            palette::FLOOR
        };
        if let Some(tint) = tint_of_room.get(rooms[i] as usize).copied().flatten() {
            colour = [0, 1, 2].map(|c| blend_channel(colour[c], tint[c], alpha));
        }
        canvas.fill_cell(g.cell_of_index(i), colour);
    }
    for (kind, colour) in [
        (obstacle::FURNITURE, palette::FURNITURE),
        (obstacle::WALL, palette::WALL),
    ] {
        for (i, &o) in obstacles.iter().enumerate() {
            if o == kind {
                canvas.fill_cell(g.cell_of_index(i), colour);
            }
        }
    }
}

/// Marks a doorway: the free cells across the opening, in the direction in which obstacles
/// (the jambs) lie on both sides; a circle when no such direction exists.
fn paint_door(canvas: &mut Canvas, scene: &Scene, position: Point2, width_m: f64) {
    let g = *scene.geometry();
    let res = g.resolution_m;
    let half = width_m.max(res) / 2.0;
    let probe = |dx: f64, dy: f64| {
        scene.is_obstacle(g.world_to_cell(Point2::new(position.x + dx, position.y + dy)))
    };
    let reach = half + res;
    let center = g.world_to_cell(position);
    let span = (half / res).ceil() as i32;
    let cells: Vec<Cell> = if probe(-reach, 0.0) && probe(reach, 0.0) {
        (-span..=span)
            .map(|d| Cell::new(center.col + d, center.row))
            .collect()
    } else if probe(0.0, -reach) && probe(0.0, reach) {
        (-span..=span)
            .map(|d| Cell::new(center.col, center.row + d))
            .collect()
    } else {
        canvas.draw_circle(position, half, palette::DOOR);
        return;
    };
    for c in cells {
        if !scene.is_obstacle(c) && (g.cell_center(c).distance(position) <= half + 0.5 * res) {
            canvas.fill_cell(c, palette::DOOR);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fit_magnifies_small_grids_and_downsamples_large_ones() {
        let small = Canvas::fit(GridGeometry::new(100, 50, 0.1, Point2::default()), 1600);
        assert_eq!((small.px_per_cell(), small.cells_per_px()), (16, 1));
        assert_eq!((small.width(), small.height()), (1600, 800));
        let large = Canvas::fit(GridGeometry::new(5000, 1000, 0.1, Point2::default()), 1600);
        assert_eq!((large.px_per_cell(), large.cells_per_px()), (1, 4));
        assert_eq!((large.width(), large.height()), (1250, 250));
        let huge = Canvas::new(
            GridGeometry::new(100, 100, 0.1, Point2::default()),
            1_000_000,
        );
        assert!(huge.width() <= MAX_CANVAS_SIDE_PX);
    }

    #[test]
    fn cells_map_to_flipped_pixel_blocks() {
        let mut c = Canvas::new(GridGeometry::new(3, 2, 0.5, Point2::new(1.0, 1.0)), 2);
        assert_eq!(c.cell_pixels(Cell::new(0, 0)), Some((0, 2, 2, 4)));
        assert_eq!(c.cell_pixels(Cell::new(2, 1)), Some((4, 0, 6, 2)));
        assert_eq!(c.cell_pixels(Cell::new(3, 0)), None);
        c.fill_cell(Cell::new(2, 1), [1, 2, 3]);
        assert_eq!(c.pixel(5, 1), Some([1, 2, 3]));
        assert_eq!(c.pixel(5, 2), Some([255, 255, 255]));
        // A world point inside cell (2, 1) lands in its block.
        let (x, y) = c.to_px(Point2::new(2.3, 1.7));
        assert_eq!(Canvas::containing(x, y), (5, 1));
    }

    #[test]
    fn blend_and_mix_interpolate() {
        assert_eq!(blend_channel(0, 255, 255), 255);
        assert_eq!(blend_channel(0, 255, 0), 0);
        assert_eq!(blend_channel(255, 0, 128), 127);
        assert_eq!(mix([0, 0, 0], [200, 100, 50], 0.5), [100, 50, 25]);
    }

    #[test]
    fn lines_far_outside_are_clipped_without_looping_forever() {
        let mut c = Canvas::new(GridGeometry::new(10, 10, 0.1, Point2::default()), 1);
        c.draw_line(Point2::new(-1e12, 0.55), Point2::new(1e12, 0.55), [0, 0, 0]);
        assert!((0..10).all(|x| c.pixel(x, 4) == Some([0, 0, 0])));
        c.draw_line(Point2::new(f64::NAN, 0.0), Point2::new(1.0, 1.0), [9, 9, 9]);
        assert!(!c.as_rgb_bytes().chunks(3).any(|p| p == [9, 9, 9]));
    }

    #[test]
    fn floor_colours_distinguish_flat_raised_and_lowered() {
        assert_eq!(floor_colour(0.0, 1.0), palette::FLOOR);
        let raised = floor_colour(0.3, 1.0);
        let lowered = floor_colour(-0.3, 1.0);
        assert_ne!(raised, palette::FLOOR);
        assert!(lowered[2] > lowered[0], "drops are blue: {lowered:?}");
        assert!(raised[0] > raised[2], "rubble is brown: {raised:?}");
        assert_eq!(floor_colour(5.0, 1.0), palette::RAISED[2]);
    }
}
