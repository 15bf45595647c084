//! `usar-console`: the operator console of paper 000 (§III HRI interface, §VII-B, Fig. 14) and
//! paper 004 (§II, Fig. 12). The whole mission of `usar mission run` ([`usar_mission`]) — a
//! team exploring with S-MCDM auctions ([`usar_team`]), a crawler building a Behavioral Trace
//! Map ([`usar_btm`]) and a MAXQ semi-autonomous robot ([`usar_rescue`]), controllers on one
//! host and one physics — runs live on its own thread and is served to browsers: plain static
//! files embedded in the binary, snapshots over a WebSocket, control messages back. The person
//! at the console is the mission's operator: every hand-off waits for their answer.
//!
//! - [`mission`]: the mission thread and what it shares with the server: frames and maps
//!   through `tokio::sync::watch` channels, so that a slow viewer only ever skips frames and
//!   never blocks the simulation;
//! - [`hook`]: the console beside the mission ([`usar_mission::MissionHook`]): pacing (pause,
//!   resume, speed-up), the person's answers at the operator's desk, teleoperation, sending a
//!   team robot to a point, the team's hypothesis and the rescuer's weights;
//! - [`protocol`]: every message a browser may send, parsed with serde into one typed enum;
//!   anything else gets an error reply;
//! - [`server`]: HTTP and WebSocket (axum), the access token, the static page; the `Host` /
//!   `Origin` allow-list and the limits on connections, message sizes, unauthenticated time and
//!   failed token attempts ([`ConsoleLimits`]);
//! - [`bench`]: many WebSocket viewers (and hostile connections held against the limits)
//!   against a running console, measuring the simulation's speed and every viewer's update rate.
//!
//! ```no_run
//! use usar_console::{ConsoleConfig, MissionConfig, start};
//! # async fn run() -> Result<(), usar_console::ConsoleError> {
//! let config = ConsoleConfig::local(MissionConfig::default());
//! let console = start(config).await?;
//! println!("{}", console.url());
//! # Ok(()) }
//! ```

pub mod bench;
pub mod clock;
mod config;
mod guard;
pub mod hook;
mod images;
pub mod mission;
pub mod protocol;
pub mod server;
mod snapshot;
mod view;

pub use self::config::{
    ConsoleConfig, ConsoleError, ConsoleLimits, MAX_TEAM_ROBOTS, MIN_OPEN_TOKEN_CHARS,
    MIN_OPEN_TOKEN_DISTINCT, MissionConfig, TOKEN_ENV, read_token_file, strong_token,
};
pub use self::server::{RunningConsole, serve_blocking, start};
pub use self::snapshot::{
    BtmLinkView, BtmNodeView, Frame, HandOffKind, HandOffView, MapView, RobotView, VictimView,
};

/// The README's examples, compiled and run as doctests.
#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;
