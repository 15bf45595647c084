//! Hostile and mistaken inputs (issue 19): each is one line on stderr naming the file or
//! option, exit code 2, and runs under a 500 MB address-space limit (`ulimit -v`), so a file
//! that declares something huge is refused before it is allocated.

use super::{assert_bad_input, shared, usar};
use std::path::Path;
use std::process::{Command, Output};

/// `usar ARGS` with its virtual memory capped at 500 MB.
fn usar_capped(args: &[&str]) -> Output {
    let quoted: Vec<String> = args
        .iter()
        .map(|a| format!("'{}'", a.replace('\'', "'\\''")))
        .collect();
    Command::new("sh")
        .arg("-c")
        .arg(format!(
            "ulimit -v 500000 && exec '{}' {}",
            env!("CARGO_BIN_EXE_usar"),
            quoted.join(" ")
        ))
        .output()
        .expect("sh runs")
}

fn write(dir: &Path, name: &str, bytes: &[u8]) -> String {
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    path.to_str().unwrap().to_string()
}

const YAML: &str = "image: map.pgm\nresolution: 0.05\norigin: [0.0, 0.0, 0.0]\nnegate: 0\n\
                    occupied_thresh: 0.65\nfree_thresh: 0.196\n";

#[test]
fn declared_sizes_past_the_limits_are_refused_before_allocating() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o.json");
    let out = out.to_str().unwrap();
    // 20 000 × 20 000 pixels in a 20-byte header.
    let bomb = write(dir.path(), "bomb.pgm", b"P5\n20000 20000\n255\n\x00");
    let run = usar_capped(&["scene", "import", &bomb, "--resolution", "0.1", "-o", out]);
    assert_bad_input(&run, "bomb.pgm: field `image size`: found 20000×20000");
    // The same image is read when the limit is raised (and then found truncated).
    let run = usar_capped(&[
        "--max-cells",
        "500000000",
        "scene",
        "import",
        &bomb,
        "--resolution",
        "0.1",
        "-o",
        out,
    ]);
    assert_bad_input(&run, "truncated");
    // Four billion training trials.
    let run = usar_capped(&["maxq", "train", "--trials", "4000000000", "--out", out]);
    assert_bad_input(&run, "--trials: found 4000000000, expected 1 to 1000000");
    // A hundred million laser beams.
    let robot = write(
        dir.path(),
        "r.toml",
        b"preset = \"wheeled\"\n[laser]\nbeams = 100000000\n",
    );
    let run = usar_capped(&[
        "plan", "--scene", "office", "--from", "5,5", "--to", "6,6", "--robot", &robot,
    ]);
    assert_bad_input(&run, "r.toml: field `laser.beams`: found 100000000");
    // An image that never ends.
    let yaml = write(
        dir.path(),
        "zero.yaml",
        YAML.replace("map.pgm", "/dev/zero").as_bytes(),
    );
    let run = usar_capped(&["scene", "import", &yaml, "-o", out]);
    assert_bad_input(&run, "/dev/zero: field `file size`");
    // 100 000 nested brackets.
    let deep = format!("image: {}\n", "[".repeat(100_000));
    let yaml = write(dir.path(), "deep.yaml", deep.as_bytes());
    assert_bad_input(
        &usar_capped(&["scene", "import", &yaml, "-o", out]),
        "deep.yaml: line",
    );
    assert!(!Path::new(out).exists(), "nothing is written on bad input");
}

#[test]
fn wrong_values_are_refused_instead_of_giving_wrong_results() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o.json");
    let out = out.to_str().unwrap();
    write(
        dir.path(),
        "map.pgm",
        b"P5\n4 4\n255\n\xfe\xfe\xfe\xfe\xfe\xfe\xfe\xfe\xfe\xfe\xfe\xfe\xfe\xfe\xfe\xfe",
    );
    for (from, to, needle) in [
        ("[0.0, 0.0, 0.0]", "[1e308, -1e308, 0]", "field `origin`"),
        (
            "resolution: 0.05",
            "resolution: 1e300",
            "field `resolution`",
        ),
        (
            "resolution: 0.05",
            "resolution: 1e-300",
            "field `resolution`",
        ),
    ] {
        let yaml = write(dir.path(), "m.yaml", YAML.replace(from, to).as_bytes());
        let run = usar_capped(&["scene", "import", &yaml, "-o", out]);
        assert_bad_input(&run, &format!("m.yaml: {needle}"));
    }
    // A misspelt key of a scene file.
    let scene = dir.path().join("s.json");
    let scene = scene.to_str().unwrap();
    assert!(
        usar(&["scene", "gen", "rubble", "--seed", "2", "-o", scene])
            .status
            .success()
    );
    let text = std::fs::read_to_string(scene).unwrap();
    let bad = write(
        dir.path(),
        "bad.json",
        text.replacen("\"victims\"", "\"victim\"", 1).as_bytes(),
    );
    assert_bad_input(
        &usar_capped(&["scene", "info", &bad]),
        "unknown field `victim`",
    );
    // A point that is not a number, a duplicate key, a scene file no command could read.
    assert_bad_input(
        &usar(&[
            "plan", "--scene", "office", "--from", "nan,3", "--to", "4,4",
        ]),
        "expected a finite number",
    );
    let robot = write(dir.path(), "r.toml", b"width_m = 0.5\nwidth_m = 0.6\n");
    let run = usar(&[
        "plan", "--scene", "office", "--from", "5,5", "--to", "6,6", "--robot", &robot,
    ]);
    assert_bad_input(&run, "r.toml: line 2, column 1: duplicate key `width_m`");
    let x = dir.path().join("x.scene");
    assert_bad_input(
        &usar(&["scene", "gen", "rubble", "-o", x.to_str().unwrap()]),
        "a scene file must end in .json",
    );
    assert!(!x.exists());
}

#[test]
fn a_real_map_turned_half_round_imports_as_the_image_turned() {
    let dir = tempfile::tempdir().unwrap();
    let depot = shared("ros/depot.yaml");
    let text = std::fs::read_to_string(&depot).unwrap();
    let image = depot.with_file_name("depot.pgm");
    // `origin: [x, y, 3.14]`, as real map repositories write it.
    let (head, _) = text.split_once("origin:").unwrap();
    let rest = text.split_once("origin:").unwrap().1;
    let after = rest.split_once('\n').map_or("", |(_, a)| a);
    let turned = format!("{head}origin: [0.0, 0.0, 3.14]\n{after}")
        .replace("depot.pgm", image.to_str().unwrap());
    let yaml = write(dir.path(), "turned.yaml", turned.as_bytes());
    let plain = write(
        dir.path(),
        "plain.yaml",
        turned.replace("3.14", "0").as_bytes(),
    );
    let info = |yaml: &str| {
        let out = dir.path().join("s.json");
        let run = usar(&[
            "scene",
            "import",
            yaml,
            "-o",
            out.to_str().unwrap(),
            "--json",
        ]);
        assert!(
            run.status.success(),
            "{}",
            String::from_utf8_lossy(&run.stderr)
        );
        let v: serde_json::Value = serde_json::from_slice(&run.stdout).unwrap();
        (v["width"].as_u64().unwrap(), v["height"].as_u64().unwrap())
    };
    assert_eq!(info(&yaml), info(&plain));
}
