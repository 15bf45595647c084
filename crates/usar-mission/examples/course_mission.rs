//! Two wheeled robots and a crawler on the test course: the crawler's BTM reaches the base
//! station over the radio and its slope and stairs become keep-out zones for the wheeled
//! robots. Run with `cargo run --release -p usar-mission --example course_mission`.

use std::sync::Arc;
use usar_mission::{MissionConfig, run_mission};
use usar_world::generate::{SceneKind, generate};

fn main() {
    let config: MissionConfig = toml::from_str(
        r#"
        scene = "course"
        minutes = 15
        [team]
        robots = 2
        robot = "wheeled"
        strategy = "nearest"
        "#,
    )
    .expect("a valid mission");
    let scene = Arc::new(generate(SceneKind::Course, 1));
    let out = run_mission(scene, &config, 1, None, |_| {}).expect("the mission runs");
    let crawler = out.crawler.as_ref().expect("a crawler");
    println!(
        "crawler: {} nodes, {} links, {:?}",
        crawler.nodes, crawler.links, crawler.nodes_by_type
    );
    println!(
        "base station: {} maps received, {} keep-out zones; team coverage {:.1} %",
        out.team.btm_maps_received,
        out.team.keep_out_zones,
        out.team.coverage * 100.0
    );
    for (a, b, r) in &out.keep_outs {
        println!(
            "  closed: ({:.1}, {:.1}) to ({:.1}, {:.1}), {:.2} m either side",
            a.x, a.y, b.x, b.y, r
        );
    }
}
