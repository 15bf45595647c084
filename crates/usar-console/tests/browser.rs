//! The end-to-end test in a real headless Chromium (Debian's `chromium` and
//! `chromium-driver`, driven over WebDriver with fantoccini): the page shows robots moving; a
//! gamepad (given to the page through the Gamepad API) drives a team robot; a click on the map
//! sends a team robot there; a victim hand-off (the person at the console is the mission's
//! operator) answered with a click ends with the victim tagged in the mission state; a stuck
//! MAXQ robot taken over with key presses moves. Screenshots go to
//! `target/console-screenshots/`.

use crate::common::start_local;
use fantoccini::actions::{InputSource, MOUSE_BUTTON_LEFT, MouseActions, PointerAction};
use fantoccini::key::Key;
use fantoccini::{Client, ClientBuilder, Locator};
use serde_json::{Value, json};
use std::f64::consts::FRAC_PI_2;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};
use usar_console::MissionConfig;

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
             (./test.sh installs them: apt-get install -y chromium chromium-driver)"
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

/// Whether two poses of the MAXQ robot are the same (it moves by cells and quarter turns).
fn same_pose(a: (f64, f64, f64), b: (f64, f64, f64)) -> bool {
    (a.0 - b.0).hypot(a.1 - b.1) < 1e-6 && (a.2 - b.2).abs() < 1e-6
}

/// What a sensible person presses for a stuck robot, from what the page shows: face a
/// pending victim lying next to it (the robot then measures it); otherwise turn toward the
/// heading the hand-off suggests and drive on. A key that left the robot where it was
/// (`tried` here) is not pressed again: then backward, the turns, forward, in that order.
fn operator_key(frame: &Value, tried: &[char]) -> Key {
    let fallback = || {
        [Key::Down, Key::Right, Key::Left, Key::Up]
            .into_iter()
            .find(|&k| !tried.contains(&char::from(k)))
            .unwrap_or(Key::Up)
    };
    let Some((x, y, theta)) = pose(frame, 0) else {
        return Key::Up;
    };
    let quarter = |a: f64| ((a / FRAC_PI_2).round() as i64).rem_euclid(4);
    let heading = quarter(theta);
    let turn_toward = |target: i64| match (target - heading).rem_euclid(4) {
        0 => None,
        3 => Some(Key::Right),
        _ => Some(Key::Left),
    };
    let adjacent = frame["victims"].as_array().and_then(|vs| {
        vs.iter()
            .filter(|v| v["status"] == "pending")
            .filter_map(|v| Some((v["x"].as_f64()? - x, v["y"].as_f64()? - y)))
            .find(|(dx, dy)| dx.hypot(*dy) < 1.2)
    });
    let suggested = frame["handoffs"].as_array().and_then(|hs| {
        hs.iter()
            .find(|h| h["kind"] == "stuck")
            .and_then(|h| h["suggested"].as_str())
            .and_then(|d| {
                ["east", "north", "west", "south"]
                    .iter()
                    .position(|n| *n == d)
            })
    });
    let sensible = match (adjacent, suggested) {
        (Some((dx, dy)), _) => turn_toward(quarter(dy.atan2(dx))),
        (None, Some(target)) => Some(turn_toward(target as i64).unwrap_or(Key::Up)),
        (None, None) => None,
    };
    sensible
        .filter(|&k| !tried.contains(&char::from(k)))
        .unwrap_or_else(fallback)
}

/// Waits until `done` holds for the page's frame; panics with `what` after `seconds`.
async fn wait_for_frame(
    c: &Client,
    seconds: u64,
    what: &str,
    done: impl Fn(&Value) -> bool,
) -> Value {
    let until = Instant::now() + Duration::from_secs(seconds);
    loop {
        let f = page_frame(c).await;
        if done(&f) {
            return f;
        }
        assert!(Instant::now() < until, "{what}: {}", f["robots"]);
        tokio::time::sleep(Duration::from_millis(150)).await;
    }
}

/// Clicks robot `id` in the robot list (selects it).
async fn select(c: &Client, id: u64) {
    c.find(Locator::Id(&format!("robot-{id}")))
        .await
        .expect("the robot in the list")
        .click()
        .await
        .expect("selects the robot");
}

/// Selects team robot `id` in the list and drives it with a gamepad (a standard-mapping pad
/// given to the page through the Gamepad API): the robot goes under operator control and moves.
/// Like a person whose robot is against rubble, the test pushes the stick forward, then back,
/// then sideways (turns), two seconds each, until the robot moves. Escape hands it back to its
/// autonomy.
async fn gamepad_drives_a_team_robot(c: &Client, id: u64) {
    select(c, id).await;
    let before = pose(&page_frame(c).await, id).expect("the robot");
    c.execute(
        "const pad = { id: 'usar test pad', index: 0, connected: true, mapping: 'standard', \
           timestamp: 0, axes: [0, 0, 0, 0], buttons: [] }; \
         window.testPad = pad; navigator.getGamepads = () => [pad];",
        vec![],
    )
    .await
    .expect("connects the pad");
    let sticks = [[0.0, -1.0], [0.0, 1.0], [-1.0, 0.0], [1.0, 0.0]];
    let until = Instant::now() + Duration::from_secs(40);
    let mut k = 0;
    'driving: loop {
        c.execute(
            "window.testPad.axes = [arguments[0], arguments[1], 0, 0];",
            vec![json!(sticks[k % 4][0]), json!(sticks[k % 4][1])],
        )
        .await
        .expect("moves the stick");
        k += 1;
        let phase = Instant::now() + Duration::from_secs(2);
        while Instant::now() < phase {
            let f = page_frame(c).await;
            if let (Some(r), Some(now)) = (robot(&f, id), pose(&f, id))
                && r["mode"] == "operator"
                && ((now.0 - before.0).hypot(now.1 - before.1) > 0.1
                    || (now.2 - before.2).abs() > 0.1)
            {
                break 'driving;
            }
            assert!(
                Instant::now() < until,
                "robot {id} did not move under the gamepad: {}",
                f["robots"]
            );
            tokio::time::sleep(Duration::from_millis(150)).await;
        }
    }
    screenshot(c, "03-gamepad").await;
    c.execute("window.testPad.axes = [0, 0, 0, 0];", vec![])
        .await
        .expect("releases the stick");
    c.find(Locator::Id("map"))
        .await
        .expect("the map")
        .send_keys(&char::from(Key::Escape).to_string())
        .await
        .expect("presses Escape");
    wait_for_frame(c, 20, "the robot did not go back to autonomy", |f| {
        robot(f, id).is_some_and(|r| r["mode"] == "autonomous")
    })
    .await;
}

/// Pauses the mission with its button, selects team robot `id` and clicks its start point on
/// the map (known free space: it came from there): the robot is sent there (paper 004's
/// operator sends robots to places) with the clicked point as its goal; Resume sets the mission
/// going again and the robot drives back toward the point.
async fn click_sends_a_team_robot(c: &Client, first: &Value, id: u64) {
    c.find(Locator::Id("pause"))
        .await
        .expect("the Pause button")
        .click()
        .await
        .expect("pauses");
    wait_for_frame(c, 20, "the mission did not pause", |f| f["paused"] == true).await;
    select(c, id).await;
    let (x, y, _) = pose(first, id).expect("the robot at the start");
    // The point in client pixels from the map canvas's centre.
    let offset = c
        .execute(
            "const c = document.getElementById('map'), r = c.getBoundingClientRect(), m = window.consoleState.map; \
             const scale = Math.min(c.width / (m.width * m.resolution_m), c.height / (m.height * m.resolution_m)); \
             const px = (arguments[0] - m.origin[0]) * scale, py = c.height - (arguments[1] - m.origin[1]) * scale; \
             return [Math.round(px * r.width / c.width - r.width / 2), Math.round(py * r.height / c.height - r.height / 2)];",
            vec![json!(x), json!(y)],
        )
        .await
        .expect("script");
    let (dx, dy) = (
        offset[0].as_f64().expect("dx"),
        offset[1].as_f64().expect("dy"),
    );
    let map = c.find(Locator::Id("map")).await.expect("the map");
    let click = MouseActions::new("mouse".into())
        .then(PointerAction::MoveToElement {
            element: map,
            duration: None,
            x: dx,
            y: dy,
        })
        .then(PointerAction::Down {
            button: MOUSE_BUTTON_LEFT,
        })
        .then(PointerAction::Up {
            button: MOUSE_BUTTON_LEFT,
        });
    c.perform_actions(click).await.expect("clicks the map");
    let until = Instant::now() + Duration::from_secs(20);
    let f = loop {
        let f = page_frame(c).await;
        if robot(&f, id).is_some_and(|r| r["task"] == "sent to a point") {
            break f;
        }
        if Instant::now() > until {
            let log = c
                .execute("return document.getElementById('log').innerText;", vec![])
                .await
                .expect("script");
            panic!(
                "robot {id} was not sent to the clicked ({x:.2}, {y:.2}): {}\npage log: {log}",
                f["robots"]
            );
        }
        tokio::time::sleep(Duration::from_millis(150)).await;
    };
    let goal = &robot(&f, id).expect("the robot")["goal"];
    let (gx, gy) = (
        goal[0].as_f64().expect("goal x"),
        goal[1].as_f64().expect("goal y"),
    );
    assert!(
        (gx - x).hypot(gy - y) < 0.5,
        "robot {id} was sent to ({gx:.2}, {gy:.2}), not to the clicked ({x:.2}, {y:.2})"
    );
    screenshot(c, "04-sent-by-click").await;
    let start = pose(&f, id).expect("the robot");
    c.find(Locator::Id("resume"))
        .await
        .expect("the Resume button")
        .click()
        .await
        .expect("resumes");
    wait_for_frame(
        c,
        60,
        "the robot did not drive back toward the clicked point",
        |f| {
            f["paused"] == false
                && pose(f, id).is_some_and(|p| {
                    (p.0 - x).hypot(p.1 - y) < ((start.0 - x).hypot(start.1 - y) - 0.2).max(0.3)
                })
        },
    )
    .await;
}

/// The end-to-end mission: the built-in mission (the office floor, the rescuer in its rubble
/// zone) with two team robots and no crawler, fast, on run seed 4 — one where, run with the
/// simulated operator, the rescuer hands navigation over within its first minute and a team
/// robot reports a warm region within eight (`usar mission run` on the same file).
fn e2e_mission() -> MissionConfig {
    let mut config = MissionConfig {
        seed: 4,
        speed: 8.0,
        ..MissionConfig::default()
    };
    let m = &mut config.mission;
    m.minutes = 30.0;
    m.team.robots = 2;
    m.crawler.enabled = false;
    m.rescuer.train_trials = 200;
    config
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
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
                matches!((a, b), (Some(a), Some(b)) if (a.0 - b.0).hypot(a.1 - b.1) > 1.0)
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

    // The team robot that has moved drives in the open: it is sent back to its start with a
    // click, then driven with a gamepad.
    click_sends_a_team_robot(&c, &first, moved[0]).await;
    gamepad_drives_a_team_robot(&c, moved[0]).await;

    // Hand-offs: answer a victim request with a click, drive a stuck robot with keys.
    let mut tagged_victim: Option<(f64, f64)> = None;
    let mut drove = false;
    let (mut stuck_handoffs, mut keys) = (0u32, 0u32);
    // The keys pressed where the robot stands that left it there.
    let (mut tried_at, mut tried) = (None, Vec::new());
    let started = Instant::now();
    let deadline = started + Duration::from_secs(300);
    while tagged_victim.is_none() || !drove {
        assert!(
            Instant::now() < deadline,
            "hand-offs did not all happen in 300 s (victim answered: {}, stuck robot driven: {drove})",
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
                screenshot(&c, "05-victim-handoff").await;
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
                let from_maxq = h["robot"] == 0;
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
                    // The victim shows as tagged; asked by the MAXQ robot, the robot carried
                    // out the tag (its count of tags grew).
                    let maxq_tagged = f["maxq_tags"].as_u64().expect("maxq_tags") > tags_before;
                    if tagged && (maxq_tagged || !from_maxq) {
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
                screenshot(&c, "06-victim-tagged").await;
            }
            Some(h) if h["kind"] == "stuck" => {
                stuck_handoffs += 1;
                // The first time with screenshots; later the robot is driven on the same way
                // (a stuck robot waits for its operator).
                if !drove {
                    screenshot(&c, "07-robot-stuck").await;
                }
                let before = pose(&f, 0).expect("robot 0");
                if tried_at.is_none_or(|p| !same_pose(p, before)) {
                    tried_at = Some(before);
                    tried.clear();
                }
                c.find(Locator::Css("button.take"))
                    .await
                    .expect("the Take over button")
                    .click()
                    .await
                    .expect("clicks Take over");
                // One command per hand-off: the robot carries it out, then asks again if it
                // is still stuck.
                let key = operator_key(&f, &tried);
                c.find(Locator::Id("map"))
                    .await
                    .expect("the map")
                    .send_keys(&char::from(key).to_string())
                    .await
                    .expect("a key press");
                keys += 1;
                let id = h["id"].clone();
                let f = wait_for_frame(&c, 60, "the stuck hand-off was not answered", |f| {
                    f["handoffs"]
                        .as_array()
                        .is_none_or(|hs| hs.first().is_none_or(|x| x["id"] != id))
                })
                .await;
                // Until the command is carried out: it moves the robot or it asks again.
                let until = Instant::now() + Duration::from_secs(30);
                let mut after = pose(&f, 0).expect("robot 0");
                while same_pose(before, after) && Instant::now() < until {
                    let f = page_frame(&c).await;
                    after = pose(&f, 0).expect("robot 0");
                    if f["handoffs"].as_array().is_some_and(|hs| !hs.is_empty()) {
                        break;
                    }
                    tokio::time::sleep(Duration::from_millis(150)).await;
                }
                if same_pose(before, after) {
                    tried.push(char::from(key));
                } else {
                    if !drove {
                        screenshot(&c, "08-driven-by-keys").await;
                    }
                    drove = true;
                }
            }
            _ => tokio::time::sleep(Duration::from_millis(200)).await,
        }
    }
    eprintln!(
        "hand-offs done in {:.0} s: {stuck_handoffs} stuck hand-offs driven with {keys} keys",
        started.elapsed().as_secs_f64()
    );
    screenshot(&c, "09-end").await;
    c.close().await.expect("closes the browser");
    console.stop().await;
}
