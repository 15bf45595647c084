//! HTTP and WebSocket (axum) around a running [`Mission`].
//!
//! | route | what | token |
//! |---|---|---|
//! | `GET /`, `/app.js`, `/style.css` | the page (embedded static files) | no |
//! | `GET /ws` | frames and maps out once the token is given, [`ClientMessage`]s in (`?token=`, or an `auth` message within the auth deadline, 5 s by default; closed with 1008 otherwise) | yes |
//! | `GET /api/state`, `/api/map` | the latest frame / map as JSON | no |
//! | `GET /api/handoff/{id}/thermal.png`, `depth.png` | a hand-off's sensor images | no |
//! | `POST /api/control` | one [`ClientMessage`] as JSON (`Authorization: Bearer TOKEN`) | yes: 401 without |
//!
//! The console binds 127.0.0.1 unless told otherwise; a non-loopback address needs an explicit,
//! strong token ([`ConsoleError::OpenBindWithoutToken`], [`ConsoleError::WeakToken`]).
//!
//! Every route, the WebSocket upgrade included, answers 403 to a `Host` or an `Origin` that is
//! not the console's own or an allowed origin ([`ConsoleConfig::allow_origins`]); a request
//! without `Origin` (curl, scripts) passes on its `Host`. Resources are bounded
//! ([`crate::ConsoleLimits`]): connections (503 beyond the cap), a plain HTTP connection's time
//! and size (one request each, `Connection: close`), a WebSocket message's size (the connection
//! is closed with 1009 when a frame header announces more than
//! [`crate::protocol::MAX_MESSAGE_BYTES`], before the payload is read), the time a WebSocket
//! may go without the token (closed with 1008), and failed token attempts per connection and
//! per peer address (429 / an error reply once used up).

use crate::config::{ConsoleConfig, ConsoleError, ConsoleLimits};
use crate::guard::{Allowed, AuthLimiter, CappedListener, Peer};
use crate::mission::{Mission, Shared, launch};
use crate::protocol::{ClientMessage, MAX_MESSAGE_BYTES, ServerMessage, parse};
use axum::Router;
use axum::extract::ws::{CloseFrame, Message, WebSocket, WebSocketUpgrade, close_code};
use axum::extract::{ConnectInfo, DefaultBodyLimit, Path, Query, Request, State};
use axum::http::{HeaderMap, HeaderValue, StatusCode, header};
use axum::middleware::{self, Next};
use axum::response::{IntoResponse, Response};
use axum::routing::{get, post};
use futures_util::{SinkExt, StreamExt};
use rand::Rng;
use serde::Deserialize;
use std::net::{IpAddr, SocketAddr};
use std::sync::Arc;
use std::time::Duration;
use tokio::sync::oneshot;

const INDEX_HTML: &str = include_str!("../static/index.html");
const APP_JS: &str = include_str!("../static/app.js");
const STYLE_CSS: &str = include_str!("../static/style.css");

#[derive(Clone)]
struct AppState {
    shared: Arc<Shared>,
    token: Arc<str>,
    allowed: Arc<Allowed>,
    limiter: Arc<AuthLimiter>,
    limits: Arc<ConsoleLimits>,
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
    config.validate()?;
    config.mission.validate()?;
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
    let limits = config.limits.clone();
    let state = AppState {
        shared: mission.shared.clone(),
        token: Arc::from(token.as_str()),
        allowed: Arc::new(Allowed::new(addr, &config.allow_origins)),
        limiter: Arc::new(AuthLimiter::new(
            limits.auth_failures_per_peer,
            limits.auth_window,
        )),
        limits: Arc::new(limits.clone()),
    };
    let app = router(state).into_make_service_with_connect_info::<Peer>();
    let listener = CappedListener::new(listener, limits.max_connections, limits.http_deadline);
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
        .layer(DefaultBodyLimit::max(MAX_MESSAGE_BYTES))
        .layer(middleware::from_fn_with_state(state.clone(), screen))
        .with_state(state)
}

fn refusal(status: StatusCode, message: String) -> Response {
    let mut response = json(status, ServerMessage::Error { message }.to_text());
    response
        .headers_mut()
        .insert(header::CONNECTION, HeaderValue::from_static("close"));
    response
}

/// Every request: 403 for a foreign `Host` or `Origin`; plain HTTP answers close their
/// connection (one request per connection, so that none lingers holding a slot).
async fn screen(State(s): State<AppState>, request: Request, next: Next) -> Response {
    let headers = request.headers();
    let host = headers
        .get(header::HOST)
        .and_then(|v| v.to_str().ok())
        .map(str::to_string)
        .or_else(|| request.uri().authority().map(|a| a.to_string()));
    match host {
        Some(h) if s.allowed.host(&h) => {}
        Some(h) => {
            return refusal(
                StatusCode::FORBIDDEN,
                format!("forbidden: Host {h:?} is not this console's address"),
            );
        }
        None => {
            return refusal(
                StatusCode::FORBIDDEN,
                "forbidden: a Host header is required".into(),
            );
        }
    }
    if let Some(origin) = headers.get(header::ORIGIN) {
        let origin = origin.to_str().unwrap_or("(not text)");
        if !s.allowed.origin(origin) {
            return refusal(
                StatusCode::FORBIDDEN,
                format!(
                    "forbidden: Origin {origin:?} is not allowed (the console's own pages and --allow-origin only)"
                ),
            );
        }
    }
    let mut response = next.run(request).await;
    if response.status() != StatusCode::SWITCHING_PROTOCOLS {
        response
            .headers_mut()
            .insert(header::CONNECTION, HeaderValue::from_static("close"));
    }
    response
}

/// 429 with `Retry-After` for a peer that has used up its failed attempts.
fn too_many(wait: Duration) -> Response {
    let seconds = wait.as_secs().max(1);
    let mut response = refusal(
        StatusCode::TOO_MANY_REQUESTS,
        format!("too many failed token attempts from this address; try again in {seconds} s"),
    );
    if let Ok(v) = HeaderValue::from_str(&seconds.to_string()) {
        response.headers_mut().insert(header::RETRY_AFTER, v);
    }
    response
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

/// `POST /api/control`: 401 without the token, 429 after too many wrong ones from the peer,
/// 413 for a body over [`MAX_MESSAGE_BYTES`], 400 for a malformed or refused message.
async fn control(
    State(s): State<AppState>,
    ConnectInfo(peer): ConnectInfo<Peer>,
    headers: HeaderMap,
    body: String,
) -> Response {
    let given = headers
        .get(header::AUTHORIZATION)
        .and_then(|v| v.to_str().ok())
        .and_then(|v| v.strip_prefix("Bearer "));
    if given.is_some()
        && let Some(wait) = s.limiter.blocked(peer.addr.ip())
    {
        return too_many(wait);
    }
    if !given.is_some_and(|g| same_token(g, &s.token)) {
        if given.is_some() {
            s.limiter.failed(peer.addr.ip());
        }
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
    let mut session = Session {
        authorized: true,
        failures: 0,
    };
    let reply = handle_text(&s, peer.addr.ip(), &body, &mut session).await;
    let status = match reply {
        ServerMessage::Error { .. } => StatusCode::BAD_REQUEST,
        _ => StatusCode::OK,
    };
    json(status, reply.to_text())
}

/// One client's standing: whether it gave the token, and how often it gave a wrong one.
struct Session {
    authorized: bool,
    failures: u32,
}

/// Parses, checks the authorization and carries out one client text.
async fn handle_text(s: &AppState, ip: IpAddr, text: &str, session: &mut Session) -> ServerMessage {
    let message = match parse(text) {
        Ok(m) => m,
        Err(e) => {
            return ServerMessage::Error {
                message: e.to_string(),
            };
        }
    };
    if let ClientMessage::Auth { token } = &message {
        if let Some(wait) = s.limiter.blocked(ip) {
            return ServerMessage::Error {
                message: format!(
                    "unauthorized: too many failed token attempts from this address; try again in {} s",
                    wait.as_secs().max(1)
                ),
            };
        }
        return if same_token(token, &s.token) {
            session.authorized = true;
            ServerMessage::Authorized
        } else {
            s.limiter.failed(ip);
            session.failures += 1;
            ServerMessage::Error {
                message: "unauthorized: wrong token".into(),
            }
        };
    }
    if message.is_control() && !session.authorized {
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

/// The WebSocket upgrade: 429 when the peer has used up its failed token attempts and gives
/// `?token=`; a wrong `?token=` counts as a failed attempt and leaves the socket unauthorized.
async fn ws_upgrade(
    State(s): State<AppState>,
    ConnectInfo(peer): ConnectInfo<Peer>,
    Query(q): Query<WsQuery>,
    upgrade: WebSocketUpgrade,
) -> Response {
    let ip = peer.addr.ip();
    let mut session = Session {
        authorized: false,
        failures: 0,
    };
    if let Some(t) = &q.token {
        if let Some(wait) = s.limiter.blocked(ip) {
            return too_many(wait);
        }
        if same_token(t, &s.token) {
            session.authorized = true;
        } else {
            s.limiter.failed(ip);
            session.failures = 1;
        }
    }
    peer.upgrading();
    upgrade
        .max_message_size(MAX_MESSAGE_BYTES)
        .max_frame_size(MAX_MESSAGE_BYTES)
        .read_buffer_size(16 * 1024)
        .on_upgrade(move |socket| viewer(s, socket, ip, session))
}

fn close(code: u16, reason: &'static str) -> Message {
    Message::Close(Some(CloseFrame {
        code,
        reason: reason.into(),
    }))
}

/// Whether a WebSocket read failed because the client's message was over the size cap.
fn too_big(e: axum::Error) -> bool {
    use tokio_tungstenite::tungstenite::Error;
    e.into_inner()
        .downcast::<Error>()
        .is_ok_and(|e| matches!(*e, Error::Capacity(_)))
}

/// One viewer: once it has given the token, the latest frame whenever there is a new one (older
/// ones are skipped when the viewer is slow) and the latest map when it changed; a reply to
/// every message. Closed with
/// 1008 when it has not given the token within the auth deadline or has given a wrong one too
/// often, with 1009 when it sends a message over the size cap.
async fn viewer(s: AppState, socket: WebSocket, ip: IpAddr, mut session: Session) {
    let (mut sink, mut stream) = socket.split();
    let mut frames = s.shared.frame_receiver();
    let mut maps = s.shared.map_receiver();
    maps.mark_changed();
    let auth_deadline = tokio::time::sleep(s.limits.auth_deadline);
    tokio::pin!(auth_deadline);
    loop {
        if session.failures >= s.limits.auth_failures_per_connection {
            let _ = sink
                .send(close(
                    close_code::POLICY,
                    "too many failed token attempts on this connection",
                ))
                .await;
            break;
        }
        let out = tokio::select! {
            _ = &mut auth_deadline, if !session.authorized => {
                let _ = sink
                    .send(close(close_code::POLICY, "no access token within the deadline"))
                    .await;
                break;
            }
            changed = frames.changed(), if session.authorized => {
                if changed.is_err() { break; }
                let text = frames.borrow_and_update().clone();
                text.to_string()
            }
            changed = maps.changed(), if session.authorized => {
                if changed.is_err() { break; }
                let text = maps.borrow_and_update().clone();
                text.to_string()
            }
            incoming = stream.next() => {
                match incoming {
                    Some(Ok(Message::Text(text))) => {
                        let was_authorized = session.authorized;
                        let reply = handle_text(&s, ip, text.as_str(), &mut session).await;
                        if session.authorized && !was_authorized {
                            frames.mark_changed();
                            maps.mark_changed();
                        }
                        reply.to_text()
                    }
                    Some(Ok(Message::Binary(_))) => ServerMessage::Error {
                        message: "binary messages are not understood; send JSON text".into(),
                    }.to_text(),
                    Some(Err(e)) => {
                        if too_big(e) {
                            let _ = sink
                                .send(close(close_code::SIZE, "message over 4096 bytes"))
                                .await;
                        }
                        break;
                    }
                    Some(Ok(Message::Close(_))) | None => break,
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
