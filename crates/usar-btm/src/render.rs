//! Drawing a BTM in the style of paper 004 Fig. 16: nodes as small squares coloured by kind,
//! searched links as straight lines, un-searched links as short stubs from their node; over
//! the scene when one is given. PNG through the world's `Canvas`, or SVG.

use crate::model::{Btm, kind};
use usar_world::render::{Canvas, RenderOptions, render_scene};
use usar_world::{GridGeometry, Point2, Scene};

/// Length of the stub drawn for an un-searched link, metres.
const STUB_M: f64 = 1.0;

fn colour(k: &str) -> [u8; 3] {
    match k {
        kind::TERMINAL => [0, 0, 0],
        kind::DIVERGENCE => [30, 90, 220],
        kind::FREE_SPACE => [20, 160, 60],
        kind::OBSTACLE => [230, 120, 0],
        kind::VICTIM => [220, 0, 0],
        _ => [140, 60, 170],
    }
}

fn hex(c: [u8; 3]) -> String {
    format!("#{:02x}{:02x}{:02x}", c[0], c[1], c[2])
}

/// Segments to draw: (from, to, searched).
fn segments(btm: &Btm) -> Vec<(Point2, Point2, bool)> {
    btm.links
        .iter()
        .filter_map(|l| {
            let a = btm.node(l.start)?;
            let p = Point2::new(a.x_m, a.y_m);
            let q = match l.end.and_then(|e| btm.node(e)) {
                Some(b) => Point2::new(b.x_m, b.y_m),
                None => Point2::new(
                    a.x_m + STUB_M * l.direction_rad.cos(),
                    a.y_m + STUB_M * l.direction_rad.sin(),
                ),
            };
            Some((p, q, l.searched))
        })
        .collect()
}

/// The bounding box of the map with a 2 m margin: (min x, min y, max x, max y).
fn bounds(btm: &Btm) -> (f64, f64, f64, f64) {
    let mut b = (
        f64::INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::NEG_INFINITY,
    );
    for (p, q, _) in segments(btm) {
        for r in [p, q] {
            b = (b.0.min(r.x), b.1.min(r.y), b.2.max(r.x), b.3.max(r.y));
        }
    }
    for n in &btm.nodes {
        b = (
            b.0.min(n.x_m),
            b.1.min(n.y_m),
            b.2.max(n.x_m),
            b.3.max(n.y_m),
        );
    }
    if !b.0.is_finite() {
        return (0.0, 0.0, 10.0, 10.0);
    }
    (b.0 - 2.0, b.1 - 2.0, b.2 + 2.0, b.3 + 2.0)
}

/// Draws the map over `scene` (or a blank area around the map) into a canvas.
pub fn draw(btm: &Btm, scene: Option<&Scene>) -> Canvas {
    draw_traced(btm, scene, &[])
}

/// [`draw`], with the path the robot drove (`trace`) drawn under the map.
pub fn draw_traced(btm: &Btm, scene: Option<&Scene>, trace: &[Point2]) -> Canvas {
    let mut canvas = match scene {
        Some(s) => render_scene(s, &RenderOptions::default()),
        None => {
            let (x0, y0, x1, y1) = bounds(btm);
            let res = 0.05;
            let g = GridGeometry::new(
                ((x1 - x0) / res).ceil() as u32,
                ((y1 - y0) / res).ceil() as u32,
                res,
                Point2::new(x0, y0),
            );
            let mut c = Canvas::fit(g, 1600);
            c.fill([255, 255, 255]);
            c
        }
    };
    canvas.draw_polyline(trace, [150, 190, 240]);
    for (p, q, searched) in segments(btm) {
        canvas.draw_line(p, q, if searched { [60, 60, 60] } else { [220, 0, 0] });
    }
    for n in &btm.nodes {
        canvas.draw_disc(Point2::new(n.x_m, n.y_m), 0.25, colour(&n.kind));
    }
    canvas
}

/// The map as a standalone SVG (1 unit = 1 cm, y up).
pub fn to_svg(btm: &Btm) -> String {
    let (x0, y0, x1, y1) = bounds(btm);
    let s = 100.0;
    let (w, h) = ((x1 - x0) * s, (y1 - y0) * s);
    let px = |p: Point2| ((p.x - x0) * s, (y1 - p.y) * s);
    let mut out = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w:.0}\" height=\"{h:.0}\" viewBox=\"0 0 {w:.0} {h:.0}\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
    );
    for (p, q, searched) in segments(btm) {
        let ((ax, ay), (bx, by)) = (px(p), px(q));
        let style = if searched {
            "stroke=\"#3c3c3c\" stroke-width=\"8\""
        } else {
            "stroke=\"#dc0000\" stroke-width=\"8\" stroke-dasharray=\"20,12\""
        };
        out += &format!(
            "<line x1=\"{ax:.1}\" y1=\"{ay:.1}\" x2=\"{bx:.1}\" y2=\"{by:.1}\" {style}/>\n"
        );
    }
    for n in &btm.nodes {
        let (x, y) = px(Point2::new(n.x_m, n.y_m));
        out += &format!(
            "<rect x=\"{:.1}\" y=\"{:.1}\" width=\"40\" height=\"40\" fill=\"{}\"><title>node {} {} {}</title></rect>\n",
            x - 20.0,
            y - 20.0,
            hex(colour(&n.kind)),
            n.id,
            n.kind,
            n.subtype.as_deref().unwrap_or("")
        );
    }
    out + "</svg>\n"
}
