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
    std::fs::write(&mission, "team_robots = 2\nwarp_drive = true\n").expect("writes");
    let out = usar(&["console", "--mission", mission.to_str().expect("utf-8")]);
    assert_bad_input(&out, "warp_drive");
    std::fs::write(&mission, "speed = -1\n").expect("writes");
    let out = usar(&["console", "--mission", mission.to_str().expect("utf-8")]);
    assert_bad_input(&out, "speed");
    std::fs::write(&mission, "team_robot = \"hovercraft\"\n").expect("writes");
    let out = usar(&["console", "--mission", mission.to_str().expect("utf-8")]);
    assert_bad_input(&out, "team_robot");
    std::fs::write(&mission, "floor_cell_m2 = 0\n").expect("writes");
    let out = usar(&["console", "--mission", mission.to_str().expect("utf-8")]);
    assert_bad_input(&out, "floor_cell_m2");
}
