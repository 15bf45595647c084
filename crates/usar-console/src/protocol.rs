//! The messages between a browser and the console, as JSON objects tagged by `"type"`.
//!
//! Every text a client sends is parsed into [`ClientMessage`]; unknown types, unknown or
//! missing fields, wrong value types and out-of-range numbers are refused with an
//! [`ServerMessage::Error`] reply naming the problem, and the connection and the mission go
//! on. Control messages need the access token, given once per WebSocket connection (the
//! `token` query parameter or an `auth` message; a WebSocket receives frames and maps only
//! once it has given it) or per HTTP request (`Authorization: Bearer TOKEN`). A text longer than [`MAX_MESSAGE_BYTES`] is refused: over
//! HTTP with 413, over a WebSocket by closing the connection (code 1009) as soon as the frame
//! header announces it, before its payload is read.

use serde::{Deserialize, Serialize};

/// A cell-robot command (the MAXQ robot's F, B and 90° turns).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum DriveCommand {
    Forward,
    Backward,
    Left,
    Right,
}

/// What a browser may send.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum ClientMessage {
    /// Authenticates this WebSocket connection for control.
    Auth { token: String },
    /// Stops the mission clock.
    Pause {},
    /// Restarts it.
    Resume {},
    /// Simulated seconds per wall-clock second (0 < factor ≤ 1000).
    Speed { factor: f64 },
    /// The answer to a victim hand-off: `tag` true confirms a victim, false rejects it.
    AnswerVictim { handoff: u64, tag: bool },
    /// One command for a robot under operator control: the MAXQ robot when it has handed
    /// navigation over (stuck), or a team robot (a short velocity pulse).
    Drive { robot: usize, command: DriveCommand },
    /// Continuous teleoperation of a team robot (keyboard held, gamepad sticks): m/s and
    /// rad/s, clamped to the robot's limits; lapses after 0.5 s without a repeat.
    Teleop {
        robot: usize,
        linear: f64,
        angular: f64,
    },
    /// Hands a teleoperated team robot back to its autonomy.
    Release { robot: usize },
    /// Sends a team robot to a point (paper 004): it follows a path on the merged map.
    SendTo { robot: usize, x: f64, y: f64 },
    /// The MAXQ robot's exploration weights w_l, w_p, w_q (paper 000 §V).
    Weights { w_l: f64, w_p: f64, w_q: f64 },
    /// The team's relevance hypothesis (paper 002): `big` or `small` rooms.
    Hypothesis { name: String },
}

impl ClientMessage {
    /// Whether the message changes the mission (and so needs the token).
    pub fn is_control(&self) -> bool {
        !matches!(self, ClientMessage::Auth { .. })
    }

    /// The message's `type`.
    pub fn name(&self) -> &'static str {
        match self {
            ClientMessage::Auth { .. } => "auth",
            ClientMessage::Pause {} => "pause",
            ClientMessage::Resume {} => "resume",
            ClientMessage::Speed { .. } => "speed",
            ClientMessage::AnswerVictim { .. } => "answer_victim",
            ClientMessage::Drive { .. } => "drive",
            ClientMessage::Teleop { .. } => "teleop",
            ClientMessage::Release { .. } => "release",
            ClientMessage::SendTo { .. } => "send_to",
            ClientMessage::Weights { .. } => "weights",
            ClientMessage::Hypothesis { .. } => "hypothesis",
        }
    }

    /// Checks numbers and names beyond what the types say.
    pub fn validate(&self) -> Result<(), ProtocolError> {
        let out_of_range = |field: &'static str, found: String, expected: &'static str| {
            Err(ProtocolError::OutOfRange {
                field,
                found,
                expected,
            })
        };
        let finite = |field: &'static str, v: f64| {
            if v.is_finite() {
                Ok(())
            } else {
                out_of_range(field, v.to_string(), "a finite number")
            }
        };
        match self {
            ClientMessage::Speed { factor } => {
                if factor.is_finite() && *factor > 0.0 && *factor <= 1000.0 {
                    Ok(())
                } else {
                    out_of_range("speed factor", factor.to_string(), "0 < factor ≤ 1000")
                }
            }
            ClientMessage::Teleop {
                linear, angular, ..
            } => finite("linear", *linear).and(finite("angular", *angular)),
            ClientMessage::SendTo { x, y, .. } => finite("x", *x).and(finite("y", *y)),
            ClientMessage::Weights { w_l, w_p, w_q } => {
                for (n, w) in [("w_l", w_l), ("w_p", w_p), ("w_q", w_q)] {
                    if !(w.is_finite() && (0.0..=100.0).contains(w)) {
                        return out_of_range(n, w.to_string(), "0 ≤ w ≤ 100");
                    }
                }
                Ok(())
            }
            ClientMessage::Hypothesis { name } => {
                if usar_team::criteria::Hypothesis::named(name).is_some() {
                    Ok(())
                } else {
                    out_of_range("hypothesis", format!("{name:?}"), "big or small")
                }
            }
            _ => Ok(()),
        }
    }
}

/// The longest client message, bytes (every valid message is far shorter).
pub const MAX_MESSAGE_BYTES: usize = 4096;

/// Why a client text was refused (its display is the error replied).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ProtocolError {
    #[error("message of {0} bytes, at most {MAX_MESSAGE_BYTES}")]
    TooLong(usize),
    /// Not JSON, or not one of the messages: serde's reason (type, field, line and column).
    #[error("malformed message: {0}")]
    Malformed(String),
    #[error("{field}: found {found}, expected {expected}")]
    OutOfRange {
        field: &'static str,
        found: String,
        expected: &'static str,
    },
}

/// Parses one client text: the message, or why it is refused.
pub fn parse(text: &str) -> Result<ClientMessage, ProtocolError> {
    if text.len() > MAX_MESSAGE_BYTES {
        return Err(ProtocolError::TooLong(text.len()));
    }
    let message: ClientMessage =
        serde_json::from_str(text).map_err(|e| ProtocolError::Malformed(e.to_string()))?;
    message.validate()?;
    Ok(message)
}

/// Replies to one client message (frames and maps are sent as prepared JSON text).
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "type", rename_all = "snake_case")]
pub enum ServerMessage {
    /// The message was carried out (or queued for the mission).
    Ok { request: String },
    /// The message was refused; nothing changed.
    Error { message: String },
    /// The connection may now control the mission.
    Authorized,
}

impl ServerMessage {
    pub fn to_text(&self) -> String {
        serde_json::to_string(self)
            .unwrap_or_else(|_| r#"{"type":"error","message":"internal"}"#.into())
    }
}
