//! The end-to-end test in a real headless Chromium (Debian's `chromium` and
//! `chromium-driver`, driven over WebDriver with fantoccini): the page shows robots moving, a
//! victim hand-off answered with a click ends with the victim tagged in the mission state, a
//! stuck MAXQ robot taken over with key presses moves. Screenshots go to
//! `target/console-screenshots/`.

use crate::common::start_local;
use fantoccini::key::Key;
use fantoccini::{Client, ClientBuilder, Locator};
use serde_json::{Value, json};
use std::f64::consts::FRAC_PI_2;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};
use usar_console::MissionConfig;
use usar_world::generate::{RubbleParams, generate_rubble};

const CHROMIUM: &str = "/usr/bin/chromium";
const CHROMEDRIVER: &str = "/usr/bin/chromedriver";

/// Ends chromedriver (and with it the browser) when the test ends, passed or failed.
struct Driver(Child);

impl Drop for Driver {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

fn free_port() -> u16 {
    std::net::TcpListener::bind("127.0.0.1:0")
        .and_then(|l| l.local_addr())
        .map(|a| a.port())
        .expect("a free port")
}

fn screenshot_dir() -> PathBuf {
    let target = std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("../../target"));
    let dir = target.join("console-screenshots");
    std::fs::create_dir_all(&dir).expect("screenshot folder");
    dir
}

async fn screenshot(c: &Client, name: &str) {
    let png = c.screenshot().await.expect("a screenshot");
    let path = screenshot_dir().join(format!("{name}.png"));
    std::fs::write(&path, png).expect("writes the screenshot");
    eprintln!("screenshot: {}", path.display());
}

async fn connect_browser() -> (Driver, Client, tempfile::TempDir) {
    for (path, package) in [(CHROMIUM, "chromium"), (CHROMEDRIVER, "chromium-driver")] {
        assert!(
            Path::new(path).exists(),
            "{path} is missing: the end-to-end console test needs Debian's {package} \
             (apt-get install -y chromium chromium-driver; .ci/run installs it)"
        );
    }
    let port = free_port();
    let driver = Driver(
        Command::new(CHROMEDRIVER)
            .arg(format!("--port={port}"))
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .expect("chromedriver starts"),
    );
    let profile = tempfile::tempdir().expect("a profile folder");
    let caps = json!({
        "goog:chromeOptions": {
            "binary": CHROMIUM,
            "args": [
                "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
                "--disable-background-networking", "--disable-component-update", "--disable-sync",
                "--disable-dev-shm-usage", "--window-size=1400,1100",
                format!("--user-data-dir={}", profile.path().display()),
            ]
        }
    });
    let caps = caps.as_object().expect("an object").clone();
    let deadline = Instant::now() + Duration::from_secs(30);
    loop {
        let connector = hyper_util::client::legacy::connect::HttpConnector::new();
        match ClientBuilder::new(connector)
            .capabilities(caps.clone())
            .connect(&format!("http://127.0.0.1:{port}"))
            .await
        {
            Ok(c) => return (driver, c, profile),
            Err(e) => {
                assert!(
                    Instant::now() < deadline,
                    "chromedriver/chromium did not start: {e}"
                );
                tokio::time::sleep(Duration::from_millis(300)).await;
            }
        }
    }
}

/// The page's latest frame.
async fn page_frame(c: &Client) -> Value {
    c.execute("return window.consoleState.frame;", vec![])
        .await
        .expect("runs the script")
}

fn robot(frame: &Value, id: u64) -> Option<&Value> {
    frame["robots"].as_array()?.iter().find(|r| r["id"] == id)
}

fn pose(frame: &Value, id: u64) -> Option<(f64, f64, f64)> {
    let r = robot(frame, id)?;
    Some((r["x"].as_f64()?, r["y"].as_f64()?, r["theta"].as_f64()?))
}

/// What a sensible person presses for a stuck robot, from what the page shows: face a
/// pending victim lying next to it (the robot then measures it), otherwise try to get it moving
/// (backward, forward, turns).
fn operator_key(frame: &Value, k: usize) -> Key {
    let Some((x, y, theta)) = pose(frame, 0) else {
        return Key::Up;
    };
    let quarter = |a: f64| ((a / FRAC_PI_2).round() as i64).rem_euclid(4);
    let heading = quarter(theta);
    let adjacent = frame["victims"].as_array().and_then(|vs| {
        vs.iter()
            .filter(|v| v["status"] == "pending")
            .filter_map(|v| Some((v["x"].as_f64()? - x, v["y"].as_f64()? - y)))
            .find(|(dx, dy)| dx.hypot(*dy) < 1.2)
    });
    if let Some((dx, dy)) = adjacent {
        match (quarter(dy.atan2(dx)) - heading).rem_euclid(4) {
            0 => {}
            3 => return Key::Right,
            _ => return Key::Left,
        }
    }
    [Key::Down, Key::Up, Key::Left, Key::Up, Key::Right, Key::Up][k % 6]
}

/// The end-to-end mission: fast, slippery (the MAXQ robot gets stuck), no BTM (speed), and
/// victims two-thirds buried, so that their exposed 0.06 m² give p ≈ 0.43 (uncertain: the
/// robot hands them to the operator).
fn e2e_mission() -> MissionConfig {
    let mut scene = generate_rubble(1, &RubbleParams::default());
    for v in &mut scene.victims {
        v.buried_fraction = (1.0 - 0.06 / v.visible_size_m2.max(0.06)).clamp(0.0, 1.0);
    }
    MissionConfig {
        scene: Some(scene),
        team_robots: 2,
        train_trials: 200,
        speed: 8.0,
        slip_probability: 0.6,
        btm: false,
        ..MissionConfig::default()
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
#[ignore = "KNOWN FAILURE (issue 7): since the merge with the MAXQ controller's new hand-off rules \
            (idle hand-offs, primitive preconditions) the stuck robot no longer moves under the \
            operator's keys; run with --ignored to reproduce"]
async fn a_person_in_chromium_sees_robots_move_answers_a_victim_and_drives_a_stuck_robot() {
    let (_driver, c, _profile) = connect_browser().await;
    let console = start_local(e2e_mission()).await;
    c.goto(&console.url()).await.expect("opens the console");

    // Robots move on the map.
    let deadline = Instant::now() + Duration::from_secs(60);
    let first = loop {
        let f = page_frame(&c).await;
        if f.is_object() && f["robots"].as_array().is_some_and(|r| r.len() == 3) {
            break f;
        }
        assert!(Instant::now() < deadline, "no frame reached the page");
        tokio::time::sleep(Duration::from_millis(200)).await;
    };
    screenshot(&c, "01-opened").await;
    let moved = loop {
        tokio::time::sleep(Duration::from_millis(500)).await;
        let f = page_frame(&c).await;
        let moved: Vec<u64> = (1..=2)
            .filter(|&id| {
                let (a, b) = (pose(&first, id), pose(&f, id));
                matches!((a, b), (Some(a), Some(b)) if (a.0 - b.0).hypot(a.1 - b.1) > 0.3)
            })
            .collect();
        if !moved.is_empty() {
            break moved;
        }
        assert!(Instant::now() < deadline, "no team robot moved on the page");
    };
    eprintln!("team robots {moved:?} moved");
    let canvas_drawn: bool = c
        .execute(
            "const c = document.getElementById('map'); const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data; \
             let lit = 0; for (let i = 0; i < d.length; i += 4) if (d[i] + d[i+1] + d[i+2] > 150) lit++; return lit > 500;",
            vec![],
        )
        .await
        .expect("script")
        .as_bool()
        .unwrap_or(false);
    assert!(canvas_drawn, "the map canvas shows nothing");
    screenshot(&c, "02-robots-moving").await;

    // Hand-offs: answer a victim request with a click, drive a stuck robot with keys.
    let mut tagged_victim: Option<(f64, f64)> = None;
    let mut drove = false;
    let deadline = Instant::now() + Duration::from_secs(240);
    while tagged_victim.is_none() || !drove {
        assert!(
            Instant::now() < deadline,
            "hand-offs did not all happen in 240 s (victim answered: {}, stuck robot driven: {drove})",
            tagged_victim.is_some()
        );
        let f = page_frame(&c).await;
        let handoff = f["handoffs"].as_array().and_then(|h| h.first()).cloned();
        match handoff {
            Some(h) if h["kind"] == "victim" => {
                let id = h["id"].as_u64().expect("id");
                let (x, y) = (h["x"].as_f64().expect("x"), h["y"].as_f64().expect("y"));
                let button = c
                    .wait()
                    .at_most(Duration::from_secs(10))
                    .for_element(Locator::Css(&format!("button.confirm[data-id='{id}']")))
                    .await
                    .expect("the Confirm button");
                screenshot(&c, "03-victim-handoff").await;
                let images: bool = c
                    .execute(
                        &format!("const i = document.querySelectorAll('#handoff-{id} img'); return i.length === 2 && [...i].every(x => x.complete && x.naturalWidth > 0);"),
                        vec![],
                    )
                    .await
                    .expect("script")
                    .as_bool()
                    .unwrap_or(false);
                assert!(images, "the thermal and depth images did not load");
                let tags_before = f["maxq_tags"].as_u64().expect("maxq_tags");
                button.click().await.expect("clicks Confirm");
                // The victim is tagged in the mission state.
                let until = Instant::now() + Duration::from_secs(30);
                loop {
                    let f = page_frame(&c).await;
                    let tagged = f["victims"].as_array().is_some_and(|vs| {
                        vs.iter().any(|v| {
                            v["status"] == "tagged"
                                && (v["x"].as_f64().unwrap_or(1e9) - x).abs() < 1e-6
                                && (v["y"].as_f64().unwrap_or(1e9) - y).abs() < 1e-6
                        })
                    });
                    // The robot's domain carried out the tag (its count of tags grew), and
                    // the victim shows as tagged.
                    if tagged && f["maxq_tags"].as_u64().expect("maxq_tags") > tags_before {
                        break;
                    }
                    assert!(
                        Instant::now() < until,
                        "the confirmed victim was not tagged: {}",
                        f["victims"]
                    );
                    tokio::time::sleep(Duration::from_millis(200)).await;
                }
                tagged_victim = Some((x, y));
                screenshot(&c, "04-victim-tagged").await;
            }
            Some(h) if h["kind"] == "stuck" => {
                // The first time with screenshots; later the robot is driven on the same way
                // (a stuck robot waits for its operator).
                if !drove {
                    screenshot(&c, "05-robot-stuck").await;
                }
                let before = pose(&f, 0).expect("robot 0");
                c.find(Locator::Css("button.take"))
                    .await
                    .expect("the Take over button")
                    .click()
                    .await
                    .expect("clicks Take over");
                let map = c.find(Locator::Id("map")).await.expect("the map");
                let until = Instant::now() + Duration::from_secs(60);
                let mut moved = false;
                let mut k = 0usize;
                loop {
                    let f = page_frame(&c).await;
                    if !f["handoffs"]
                        .as_array()
                        .is_some_and(|h| h.iter().any(|h| h["kind"] == "stuck"))
                    {
                        break;
                    }
                    let now = pose(&f, 0).expect("robot 0");
                    if (now.0 - before.0).hypot(now.1 - before.1) > 1e-6
                        || (now.2 - before.2).abs() > 1e-6
                    {
                        moved = true;
                    }
                    assert!(
                        Instant::now() < until,
                        "robot 0 stayed stuck under the operator's keys"
                    );
                    map.send_keys(&char::from(operator_key(&f, k)).to_string())
                        .await
                        .expect("a key press");
                    k += 1;
                    tokio::time::sleep(Duration::from_millis(400)).await;
                }
                let after = pose(&page_frame(&c).await, 0).expect("robot 0");
                moved |= (after.0 - before.0).hypot(after.1 - before.1) > 1e-6
                    || (after.2 - before.2).abs() > 1e-6;
                // A key press that bumps into rubble can end the hand-off without moving the
                // robot (the bump corrects its map, which is progress); the robot soon gets
                // stuck again on this slippery floor, and the overall deadline above fails the
                // test if it is never seen to move under the keys.
                if moved {
                    if !drove {
                        screenshot(&c, "06-driven-by-keys").await;
                    }
                    drove = true;
                }
            }
            _ => tokio::time::sleep(Duration::from_millis(200)).await,
        }
    }
    screenshot(&c, "07-end").await;
    c.close().await.expect("closes the browser");
    console.stop().await;
}
