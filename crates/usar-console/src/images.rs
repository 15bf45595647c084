//! The sensor views shown with a victim hand-off, as PNG images: the thermal region around the
//! possible victim and the depth (height) profile ahead of the robot, both read from the scene
//! the sensors observe.

use std::io::Cursor;
use usar_world::{Point2, Scene};

/// Pixels per side of a hand-off image.
const SIDE_PX: u32 = 96;
/// Ambient temperature of the thermal view, °C.
const AMBIENT_C: f64 = 18.0;

fn encode(width: u32, height: u32, rgb: Vec<u8>) -> Vec<u8> {
    let mut bytes = Vec::new();
    if let Some(img) = image::RgbImage::from_raw(width, height, rgb) {
        // Encoding an in-memory RGB buffer cannot fail short of running out of memory.
        let _ = img.write_to(&mut Cursor::new(&mut bytes), image::ImageFormat::Png);
    }
    bytes
}

/// An "iron" palette: black, purple, red, orange, yellow, white over 0…1.
fn iron(t: f64) -> [u8; 3] {
    const STOPS: [[f64; 3]; 6] = [
        [0.0, 0.0, 0.0],
        [80.0, 0.0, 120.0],
        [200.0, 20.0, 60.0],
        [250.0, 120.0, 0.0],
        [255.0, 220.0, 40.0],
        [255.0, 255.0, 255.0],
    ];
    let x = t.clamp(0.0, 1.0) * (STOPS.len() - 1) as f64;
    let k = (x.floor() as usize).min(STOPS.len() - 2);
    let f = x - k as f64;
    let c = |i: usize| (STOPS[k][i] + f * (STOPS[k + 1][i] - STOPS[k][i])) as u8;
    [c(0), c(1), c(2)]
}

/// The thermal region: temperatures over a square three cells wide centred on `centre`
/// (`cell_m` the cell side), victims and other heat sources as discs of their exposed size,
/// mapped 15–45 °C onto the palette.
pub fn thermal_png(scene: &Scene, centre: Point2, cell_m: f64) -> Vec<u8> {
    let half = 1.5 * cell_m;
    let sources: Vec<(Point2, f64, f64)> = scene
        .victims
        .iter()
        .map(|v| (v.position, v.heat_c, v.exposed_size_m2()))
        .chain(
            scene
                .heat_sources
                .iter()
                .map(|h| (h.position, h.heat_c, h.size_m2)),
        )
        .filter(|(p, _, _)| {
            (p.x - centre.x).abs() < 2.0 * half && (p.y - centre.y).abs() < 2.0 * half
        })
        .collect();
    let mut rgb = Vec::with_capacity((SIDE_PX * SIDE_PX * 3) as usize);
    for py in 0..SIDE_PX {
        for px in 0..SIDE_PX {
            let x = centre.x - half + (f64::from(px) + 0.5) / f64::from(SIDE_PX) * 2.0 * half;
            let y = centre.y + half - (f64::from(py) + 0.5) / f64::from(SIDE_PX) * 2.0 * half;
            let mut t = AMBIENT_C;
            for &(p, heat, size) in &sources {
                let r = (size.max(0.01) / std::f64::consts::PI).sqrt();
                let d = ((x - p.x).powi(2) + (y - p.y).powi(2)).sqrt();
                // A warm disc with a soft rim of half its radius.
                let w = ((1.5 * r - d) / (0.5 * r)).clamp(0.0, 1.0);
                t = t.max(AMBIENT_C + w * (heat - AMBIENT_C));
            }
            rgb.extend_from_slice(&iron((t - 15.0) / 30.0));
        }
    }
    encode(SIDE_PX, SIDE_PX, rgb)
}

/// The depth profile ahead: the floor heights and obstacles over the two cells in front of a
/// robot at `from` facing `heading` (0–3, counter-clockwise from east), as the depth array
/// D_xy sees them, grey from −0.3 m (dark) to +0.3 m (light) relative to the robot's floor;
/// walls and furniture are drawn red.
pub fn depth_png(scene: &Scene, from: Point2, heading: u8, cell_m: f64) -> Vec<u8> {
    let g = *scene.geometry();
    let angle = f64::from(heading) * std::f64::consts::FRAC_PI_2;
    let (fx, fy) = (angle.cos(), angle.sin());
    let (lx, ly) = (-fy, fx);
    let floor = |p: Point2| {
        g.checked_index(g.world_to_cell(p)).map(|i| {
            (
                scene.floor_height_m.as_slice()[i],
                scene.obstacle.as_slice()[i],
            )
        })
    };
    let base = floor(from).map_or(0.0, |(h, _)| f64::from(h));
    let mut rgb = Vec::with_capacity((SIDE_PX * SIDE_PX * 3) as usize);
    for py in 0..SIDE_PX {
        for px in 0..SIDE_PX {
            // Image up = ahead (0.5 to 2.5 cells), image left/right = the robot's left/right.
            let ahead = (0.5 + 2.0 * (1.0 - (f64::from(py) + 0.5) / f64::from(SIDE_PX))) * cell_m;
            let side = (0.5 - (f64::from(px) + 0.5) / f64::from(SIDE_PX)) * 1.5 * cell_m;
            let p = Point2::new(
                from.x + ahead * fx + side * lx,
                from.y + ahead * fy + side * ly,
            );
            let colour = match floor(p) {
                None => [40, 40, 60],
                Some((_, o)) if o != 0 => [190, 40, 40],
                Some((h, _)) => {
                    let v = ((f64::from(h) - base + 0.3) / 0.6).clamp(0.0, 1.0);
                    let g = (30.0 + 220.0 * v) as u8;
                    [g, g, g]
                }
            };
            rgb.extend_from_slice(&colour);
        }
    }
    encode(SIDE_PX, SIDE_PX, rgb)
}
