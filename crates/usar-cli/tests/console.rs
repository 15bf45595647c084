//! `usar console`: what it refuses before serving anything.

use super::{assert_bad_input, usar};

#[test]
fn serving_beyond_loopback_without_a_token_is_refused() {
    let out = usar(&["console", "--bind", "0.0.0.0:0"]);
    assert_bad_input(&out, "needs an explicit --token");
}

#[test]
fn a_bad_bind_address_or_mission_file_is_bad_input() {
    let out = usar(&["console", "--bind", "localhost"]);
    assert_bad_input(&out, "--bind localhost");
    let dir = tempfile::tempdir().expect("temp dir");
    let mission = dir.path().join("mission.toml");
    for (text, field) in [
        ("team_robots = 2\nwarp_drive = true\n", "warp_drive"),
        ("speed = -1\n", "speed"),
        ("team_robot = \"hovercraft\"\n", "team_robot"),
        ("floor_cell_m2 = 0\n", "floor_cell_m2"),
    ] {
        std::fs::write(&mission, text).expect("writes");
        let out = usar(&["console", "--mission", mission.to_str().expect("utf-8")]);
        assert_bad_input(&out, field);
    }
}
