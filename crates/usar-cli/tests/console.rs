//! `usar console`: what it refuses before serving anything, and where it takes its token from.

use super::{assert_bad_input, usar, usar_env};
use std::io::{BufRead, BufReader, Read, Write};
use std::process::{Command, Stdio};

#[test]
fn serving_beyond_loopback_without_a_strong_token_is_refused() {
    let out = usar(&["console", "--bind", "0.0.0.0:0"]);
    assert_bad_input(&out, "needs an explicit access token");
    let out = usar(&["console", "--bind", "0.0.0.0:0", "--token", "a"]);
    assert_bad_input(
        &out,
        "at least 24 characters with at least 10 different ones",
    );
    // The environment variable is read (and held to the same rule).
    let out = usar_env(
        &["console", "--bind", "0.0.0.0:0"],
        &[("USAR_CONSOLE_TOKEN", "aaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaa")],
    );
    assert_bad_input(&out, "too weak");
    let dir = tempfile::tempdir().expect("temp dir");
    let missing = dir.path().join("missing-token");
    let out = usar(&["console", "--token-file", missing.to_str().expect("utf-8")]);
    assert_bad_input(&out, "--token-file");
    let out = usar(&["console", "--allow-origin", "evil.example"]);
    assert_bad_input(&out, "--allow-origin evil.example");
    let out = usar(&["console", "--max-connections", "0"]);
    assert_bad_input(&out, "--max-connections");
}

/// Starts `usar console` on a free loopback port with a small mission; the child, its
/// standard output (kept open: the console prints more lines) and the address it printed.
fn serve(
    dir: &std::path::Path,
    args: &[&str],
    env: &[(&str, &str)],
) -> (
    std::process::Child,
    BufReader<std::process::ChildStdout>,
    String,
) {
    let mission = dir.join("small.toml");
    std::fs::write(
        &mission,
        "minutes = 5\n[team]\nrobots = 1\n[crawler]\nenabled = false\n[rescuer]\ntrain_trials = 50\n",
    )
    .expect("writes");
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_usar"));
    cmd.args(["console", "--bind", "127.0.0.1:0", "--mission"])
        .arg(&mission)
        .args(args)
        .env_remove("USAR_CONSOLE_TOKEN")
        .stdout(Stdio::piped())
        .stderr(Stdio::null());
    for (k, v) in env {
        cmd.env(k, v);
    }
    let mut child = cmd.spawn().expect("usar starts");
    let mut first = String::new();
    let mut stdout = BufReader::new(child.stdout.take().expect("stdout"));
    stdout.read_line(&mut first).expect("reads the first line");
    let addr = first
        .trim()
        .strip_prefix("usar console: http://")
        .and_then(|rest| rest.split('/').next())
        .unwrap_or_else(|| panic!("no address in {first:?}"))
        .to_string();
    assert!(
        !first.contains("token="),
        "a given token is not printed: {first}"
    );
    (child, stdout, addr)
}

/// `POST /api/control` with a bearer token; the status code.
fn control(addr: &str, token: &str) -> u16 {
    let mut tcp = std::net::TcpStream::connect(addr).expect("connects");
    tcp.set_read_timeout(Some(std::time::Duration::from_secs(60)))
        .expect("a timeout");
    let body = r#"{"type":"resume"}"#;
    write!(
        tcp,
        "POST /api/control HTTP/1.1\r\nHost: {addr}\r\nAuthorization: Bearer {token}\r\n\
         Content-Type: application/json\r\nContent-Length: {}\r\nConnection: close\r\n\r\n{body}",
        body.len()
    )
    .expect("writes");
    let mut answer = String::new();
    let _ = tcp.read_to_string(&mut answer);
    answer
        .split_whitespace()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(0)
}

#[test]
fn the_token_comes_from_a_file_or_the_environment() {
    let token = "3f9a1c07d2b84e6f9a0c5d1e7b2f4a68";
    let dir = tempfile::tempdir().expect("temp dir");
    let file = dir.path().join("token");
    std::fs::write(&file, format!("{token}\n")).expect("writes");
    let by_file = ["--token-file", file.to_str().expect("utf-8")];
    let by_env = [("USAR_CONSOLE_TOKEN", token)];
    for (args, env) in [(&by_file[..], &[][..]), (&[][..], &by_env[..])] {
        let (mut child, _stdout, addr) = serve(dir.path(), args, env);
        let (right, wrong) = (control(&addr, token), control(&addr, "guess"));
        let _ = child.kill();
        let _ = child.wait();
        assert_eq!((right, wrong), (200, 401), "{args:?} {env:?}");
    }
}

#[test]
fn a_bad_bind_address_or_mission_file_is_bad_input() {
    let out = usar(&["console", "--bind", "localhost"]);
    assert_bad_input(&out, "--bind localhost");
    let out = usar(&["console", "--speed=-1"]);
    assert_bad_input(&out, "speed");
    let dir = tempfile::tempdir().expect("temp dir");
    let mission = dir.path().join("mission.toml");
    for (text, field) in [
        ("[team]\nrobots = 2\nwarp_drive = true\n", "warp_drive"),
        ("speed = 2\n", "speed"),
        ("[team]\nrobot = \"hovercraft\"\n", "hovercraft"),
        ("[rescuer]\nzone_cells = 0\n", "rescuer.zone_cells"),
        (
            "[rescuer]\ntrain_trials = 4000000000\n",
            "rescuer.train_trials",
        ),
        ("[team]\nrobots = 100000\n", "team.robots"),
    ] {
        std::fs::write(&mission, text).expect("writes");
        let out = usar(&["console", "--mission", mission.to_str().expect("utf-8")]);
        assert_bad_input(&out, field);
        assert_bad_input(&out, "mission.toml");
    }
}
