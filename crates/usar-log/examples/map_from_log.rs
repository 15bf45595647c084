//! Reads a real robot log and builds its occupancy grid with scan matching:
//! `cargo run --release -p usar-log --example map_from_log -- LOG`.

use usar_log::mapping::{MapParams, build_map};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let path = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "../shared/datasets/duke_dpslam_loop5/loop5.log".into());
    let log = usar_log::read_log(std::path::Path::new(&path), None)?;
    let summary = log.summary();
    println!(
        "{}: {:?}, {} scans of {}-{} beams, no return at {:?} m ({:?})",
        path,
        summary.format,
        summary.scans,
        summary.beams_min,
        summary.beams_max,
        summary.no_return_m,
        summary.no_return_source
    );
    let map = build_map(&log, &MapParams::default())?;
    let g = map.grid.geometry();
    println!(
        "{} x {} cells, {:.0} m² known; {} scans matched, {} rejected; estimate vs odometry: final {:.2} m",
        g.width,
        g.height,
        map.grid.known_area_m2(),
        map.matched,
        map.rejected,
        map.drift.estimate_vs_odometry.final_m
    );
    if let Some(png) = std::env::args().nth(2) {
        usar_log::output::picture(&map, &map.frontiers(0.5), 1600)
            .save_png(std::path::Path::new(&png))?;
    }
    Ok(())
}
