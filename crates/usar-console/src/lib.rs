//! `usar-console`: the operator console of paper 000 (§III HRI interface, §VII-B, Fig. 14) and
//! paper 004 (§II, Fig. 12). A live simulated mission — one MAXQ semi-autonomous robot
//! ([`usar_rescue`]), a small team exploring with S-MCDM auctions ([`usar_team`]) and a
//! Behavioral Trace Map being built ([`usar_btm`]) — runs on its own threads and is served to
//! browsers: plain static files embedded in the binary, snapshots over a WebSocket, control
//! messages back.
//!
//! - [`mission`]: the mission threads, paced by one [`clock::MissionClock`] (pause, resume,
//!   speed-up), publishing snapshots through `tokio::sync::watch` channels so that a slow viewer
//!   only ever skips frames and never blocks the simulation;
//! - [`operator`]: the console's side of the [`usar_rescue::operator::HandOff`] interface —
//!   the robot's hand-offs wait for a person's answer, which the robot learns from as it does
//!   from the simulated operator;
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
mod images;
pub mod mission;
pub mod operator;
pub mod protocol;
mod scene_setup;
pub mod server;
mod snapshot;
mod team_hook;

pub use self::config::{
    ConsoleConfig, ConsoleError, ConsoleLimits, MAX_MINUTES, MAX_TEAM_ROBOTS, MIN_OPEN_TOKEN_CHARS,
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
