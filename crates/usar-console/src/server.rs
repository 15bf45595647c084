//! HTTP and WebSocket (axum) around a running [`Mission`].
//!
//! | route | what | token |
//! |---|---|---|
//! | `GET /`, `/app.js`, `/style.css` | the page (embedded static files) | no |
//! | `GET /ws` | frames and maps out, [`ClientMessage`]s in (`?token=` or an `auth` message for control) | for control |
//! | `GET /api/state`, `/api/map` | the latest frame / map as JSON | no |
//! | `GET /api/handoff/{id}/thermal.png`, `depth.png` | a hand-off's sensor images | no |
//! | `POST /api/control` | one [`ClientMessage`] as JSON (`Authorization: Bearer TOKEN`) | yes: 401 without |
//!
//! The console binds 127.0.0.1 unless told otherwise; a non-loopback address needs an explicit
//! token ([`ConsoleError::OpenBindWithoutToken`]).

use crate::config::{ConsoleConfig, ConsoleError};
use crate::mission::{Mission, Shared, launch};
use crate::protocol::{ClientMessage, ServerMessage, parse};
use axum::Router;
use axum::extract::ws::{Message, WebSocket, WebSocketUpgrade};
use axum::extract::{Path, Query, State};
use axum::http::{HeaderMap, StatusCode, header};
use axum::response::{IntoResponse, Response};
use axum::routing::{get, post};
use futures_util::{SinkExt, StreamExt};
use rand::Rng;
use serde::Deserialize;
use std::net::SocketAddr;
use std::sync::Arc;
use tokio::sync::oneshot;

const INDEX_HTML: &str = include_str!("../static/index.html");
const APP_JS: &str = include_str!("../static/app.js");
const STYLE_CSS: &str = include_str!("../static/style.css");

#[derive(Clone)]
struct AppState {
    shared: Arc<Shared>,
    token: Arc<str>,
}

/// A console serving its mission; stops both when dropped or [`RunningConsole::stop`]ped.
pub struct RunningConsole {
    pub addr: SocketAddr,
    pub token: String,
    mission: Option<Mission>,
    shutdown: Option<oneshot::Sender<()>>,
    server: Option<tokio::task::JoinHandle<()>>,
}

impl RunningConsole {
    /// The page's address with the access token.
    pub fn url(&self) -> String {
        format!("http://{}/?token={}", self.addr, self.token)
    }

    /// The mission's shared state (clock, steps, channels).
    pub fn shared(&self) -> Option<&Arc<Shared>> {
        self.mission.as_ref().map(|m| &m.shared)
    }

    /// Stops the server and the mission.
    pub async fn stop(mut self) {
        self.halt();
        if let Some(server) = self.server.take() {
            let _ = server.await;
        }
        if let Some(mut mission) = self.mission.take() {
            let _ = tokio::task::spawn_blocking(move || mission.stop()).await;
        }
    }

    fn halt(&mut self) {
        if let Some(tx) = self.shutdown.take() {
            let _ = tx.send(());
        }
        if let Some(m) = &self.mission {
            m.shared.clock.stop();
        }
    }
}

impl Drop for RunningConsole {
    fn drop(&mut self) {
        self.halt();
    }
}

/// A random 128-bit token in hex.
fn random_token() -> String {
    let v: u128 = rand::rng().random();
    format!("{v:032x}")
}

/// Compares in time independent of where the strings differ.
fn same_token(given: &str, token: &str) -> bool {
    given.len() == token.len()
        && given
            .bytes()
            .zip(token.bytes())
            .fold(0u8, |acc, (a, b)| acc | (a ^ b))
            == 0
}

/// Starts the mission and the server.
pub async fn start(config: ConsoleConfig) -> Result<RunningConsole, ConsoleError> {
    if !config.bind.ip().is_loopback() && config.token.is_none() {
        return Err(ConsoleError::OpenBindWithoutToken(config.bind));
    }
    if let Some(t) = &config.token
        && t.trim().is_empty()
    {
        return Err(ConsoleError::Field {
            field: "token".into(),
            message: "empty; expected a secret string".into(),
        });
    }
    let token = config.token.clone().unwrap_or_else(random_token);
    let listener = tokio::net::TcpListener::bind(config.bind)
        .await
        .map_err(|source| ConsoleError::Bind {
            addr: config.bind,
            source,
        })?;
    let addr = listener.local_addr().map_err(|source| ConsoleError::Bind {
        addr: config.bind,
        source,
    })?;
    let mission_config = config.mission.clone();
    let mission = tokio::task::spawn_blocking(move || launch(mission_config))
        .await
        .map_err(|e| ConsoleError::Field {
            field: "mission".into(),
            message: format!("set-up failed: {e}"),
        })??;
    let state = AppState {
        shared: mission.shared.clone(),
        token: Arc::from(token.as_str()),
    };
    let app = router(state);
    let (tx, rx) = oneshot::channel::<()>();
    let server = tokio::spawn(async move {
        let _ = axum::serve(listener, app)
            .with_graceful_shutdown(async {
                let _ = rx.await;
            })
            .await;
    });
    Ok(RunningConsole {
        addr,
        token,
        mission: Some(mission),
        shutdown: Some(tx),
        server: Some(server),
    })
}

fn router(state: AppState) -> Router {
    Router::new()
        .route(
            "/",
            get(|| async { static_file("text/html; charset=utf-8", INDEX_HTML) }),
        )
        .route(
            "/app.js",
            get(|| async { static_file("text/javascript; charset=utf-8", APP_JS) }),
        )
        .route(
            "/style.css",
            get(|| async { static_file("text/css; charset=utf-8", STYLE_CSS) }),
        )
        .route("/ws", get(ws_upgrade))
        .route("/api/state", get(latest_frame))
        .route("/api/map", get(latest_map))
        .route("/api/handoff/{id}/{which}", get(handoff_image))
        .route("/api/control", post(control))
        .with_state(state)
}

fn static_file(content_type: &'static str, body: &'static str) -> Response {
    (
        [
            (header::CONTENT_TYPE, content_type),
            (header::CACHE_CONTROL, "no-cache"),
        ],
        body,
    )
        .into_response()
}

fn json(status: StatusCode, body: String) -> Response {
    (status, [(header::CONTENT_TYPE, "application/json")], body).into_response()
}

async fn latest_frame(State(s): State<AppState>) -> Response {
    let text = s.shared.frame_receiver().borrow().clone();
    json(StatusCode::OK, text.to_string())
}

async fn latest_map(State(s): State<AppState>) -> Response {
    let text = s.shared.map_receiver().borrow().clone();
    json(StatusCode::OK, text.to_string())
}

async fn handoff_image(
    State(s): State<AppState>,
    Path((id, which)): Path<(u64, String)>,
) -> Response {
    match s.shared.image(id, &which) {
        Some(png) => ([(header::CONTENT_TYPE, "image/png")], png).into_response(),
        None => (StatusCode::NOT_FOUND, "no such hand-off image").into_response(),
    }
}

/// `POST /api/control`: 401 without the token, 400 for a malformed or refused message.
async fn control(State(s): State<AppState>, headers: HeaderMap, body: String) -> Response {
    let given = headers
        .get(header::AUTHORIZATION)
        .and_then(|v| v.to_str().ok())
        .and_then(|v| v.strip_prefix("Bearer "));
    if !given.is_some_and(|g| same_token(g, &s.token)) {
        return json(
            StatusCode::UNAUTHORIZED,
            ServerMessage::Error {
                message:
                    "unauthorized: control needs the access token (Authorization: Bearer TOKEN)"
                        .into(),
            }
            .to_text(),
        );
    }
    let reply = handle_text(&s, &body, &mut true).await;
    let status = match reply {
        ServerMessage::Error { .. } => StatusCode::BAD_REQUEST,
        _ => StatusCode::OK,
    };
    json(status, reply.to_text())
}

/// Parses, checks the authorization and carries out one client text.
async fn handle_text(s: &AppState, text: &str, authorized: &mut bool) -> ServerMessage {
    let message = match parse(text) {
        Ok(m) => m,
        Err(message) => return ServerMessage::Error { message },
    };
    if let ClientMessage::Auth { token } = &message {
        return if same_token(token, &s.token) {
            *authorized = true;
            ServerMessage::Authorized
        } else {
            ServerMessage::Error {
                message: "unauthorized: wrong token".into(),
            }
        };
    }
    if message.is_control() && !*authorized {
        return ServerMessage::Error {
            message: "unauthorized: control needs the access token".into(),
        };
    }
    let request = message.name().to_string();
    match s.shared.control(message).await {
        Ok(()) => ServerMessage::Ok { request },
        Err(message) => ServerMessage::Error { message },
    }
}

#[derive(Deserialize)]
struct WsQuery {
    token: Option<String>,
}

async fn ws_upgrade(
    State(s): State<AppState>,
    Query(q): Query<WsQuery>,
    upgrade: WebSocketUpgrade,
) -> Response {
    let authorized = q.token.is_some_and(|t| same_token(&t, &s.token));
    upgrade.on_upgrade(move |socket| viewer(s, socket, authorized))
}

/// One viewer: the latest frame whenever there is a new one (older ones are skipped when the
/// viewer is slow), the latest map when it changed, and a reply to every message.
async fn viewer(s: AppState, socket: WebSocket, mut authorized: bool) {
    let (mut sink, mut stream) = socket.split();
    let mut frames = s.shared.frame_receiver();
    let mut maps = s.shared.map_receiver();
    maps.mark_changed();
    loop {
        let out = tokio::select! {
            changed = frames.changed() => {
                if changed.is_err() { break; }
                let text = frames.borrow_and_update().clone();
                text.to_string()
            }
            changed = maps.changed() => {
                if changed.is_err() { break; }
                let text = maps.borrow_and_update().clone();
                text.to_string()
            }
            incoming = stream.next() => {
                match incoming {
                    Some(Ok(Message::Text(text))) => handle_text(&s, text.as_str(), &mut authorized).await.to_text(),
                    Some(Ok(Message::Binary(_))) => ServerMessage::Error {
                        message: "binary messages are not understood; send JSON text".into(),
                    }.to_text(),
                    Some(Ok(Message::Close(_))) | None | Some(Err(_)) => break,
                    Some(Ok(_)) => continue,
                }
            }
        };
        if sink.send(Message::Text(out.into())).await.is_err() {
            break;
        }
    }
}

/// Runs a console until Ctrl-C (for the `usar console` command): `on_start` gets the running
/// console (to print its address and token).
pub fn serve_blocking(
    config: ConsoleConfig,
    on_start: impl FnOnce(&RunningConsole),
) -> Result<(), ConsoleError> {
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .enable_all()
        .build()
        .map_err(|source| ConsoleError::Bind {
            addr: config.bind,
            source,
        })?;
    runtime.block_on(async move {
        let console = start(config).await?;
        on_start(&console);
        let _ = tokio::signal::ctrl_c().await;
        console.stop().await;
        Ok(())
    })
}
