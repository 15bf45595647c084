//! What keeps a console to the clients it is meant for and its resources bounded:
//!
//! - [`Allowed`]: the `Host` and `Origin` allow-list (a foreign `Host` is a DNS-rebinding
//!   attempt, a foreign `Origin` another site's page; both get 403);
//! - [`AuthLimiter`]: failed token attempts per peer address within a window;
//! - [`CappedListener`]: at most `max_connections` TCP connections at once (one more is answered
//!   503 and closed), each plain HTTP connection limited in time and in the bytes it may send
//!   until it is upgraded to a WebSocket.

use axum::extract::connect_info::Connected;
use axum::serve::{IncomingStream, Listener};
use std::collections::{BTreeSet, HashMap};
use std::future::Future;
use std::io;
use std::net::{IpAddr, Ipv6Addr, SocketAddr};
use std::pin::Pin;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::task::{Context, Poll};
use std::time::{Duration, Instant};
use tokio::io::{AsyncRead, AsyncReadExt, AsyncWrite, AsyncWriteExt, ReadBuf};
use tokio::net::{TcpListener, TcpStream};
use tokio::sync::{OwnedSemaphorePermit, Semaphore};
use tokio::time::Sleep;

/// The bytes a connection may send before it is upgraded to a WebSocket: a request head with
/// its cookies and a control message.
const HTTP_REQUEST_BYTES: usize = 64 * 1024;
/// Connections being answered 503 at once; beyond, they are closed without an answer.
const REFUSING_AT_ONCE: usize = 64;

/// An `--allow-origin` value checked and lower-cased: `http` or `https`, `://`, a host and an
/// optional port, nothing else.
pub(crate) fn parse_origin(origin: &str) -> Result<String, String> {
    let lower = origin.to_ascii_lowercase();
    let Some((scheme, authority)) = lower.split_once("://") else {
        return Err("expected SCHEME://HOST[:PORT], e.g. https://console.example.org".into());
    };
    if scheme != "http" && scheme != "https" {
        return Err(format!("scheme {scheme:?}; expected http or https"));
    }
    if authority.is_empty()
        || authority.chars().any(|c| {
            matches!(c, '/' | '?' | '#' | '@' | '\\') || c.is_whitespace() || c.is_control()
        })
    {
        return Err(
            "expected SCHEME://HOST[:PORT] without a path, query, user or trailing slash".into(),
        );
    }
    let (host, port) = match authority.strip_prefix('[') {
        Some(rest) => {
            let Some((v6, after)) = rest.split_once(']') else {
                return Err("unclosed [ in the host".into());
            };
            match after {
                "" => (v6, None),
                _ => match after.strip_prefix(':') {
                    Some(port) => (v6, Some(port)),
                    None => return Err(format!("{after:?} after the address; expected :PORT")),
                },
            }
        }
        None => match authority.split_once(':') {
            Some((host, port)) => (host, Some(port)),
            None => (authority, None),
        },
    };
    if host.is_empty() {
        return Err("no host; expected SCHEME://HOST[:PORT]".into());
    }
    if let Some(port) = port
        && !port.parse::<u16>().is_ok_and(|p| p > 0)
    {
        return Err(format!("port {port:?}; expected 1 to 65535"));
    }
    Ok(lower)
}

/// The `Host` values and `Origin`s a console answers.
#[derive(Debug)]
pub(crate) struct Allowed {
    /// `host:port` values (lower case).
    hosts: BTreeSet<String>,
    /// The console's own origins (`http://` + each of its own hosts).
    own_hosts: BTreeSet<String>,
    /// `--allow-origin` values (lower case).
    origins: BTreeSet<String>,
    /// On 0.0.0.0 / `::`: any IP address at this port (an address is never a rebinding
    /// attack's `Host`, which is the attacker's name).
    any_ip_at: Option<u16>,
}

impl Allowed {
    /// For a console bound at `bound` (its actual port) with extra origins (already checked).
    pub(crate) fn new(bound: SocketAddr, extra_origins: &[String]) -> Self {
        let port = bound.port();
        let mut own = BTreeSet::new();
        own.insert(bound.to_string());
        if bound.ip().is_loopback() {
            for host in ["localhost", "127.0.0.1", "[::1]"] {
                own.insert(format!("{host}:{port}"));
            }
        }
        if port == 80 {
            let portless: Vec<String> = own
                .iter()
                .filter_map(|h| h.strip_suffix(":80").map(str::to_string))
                .collect();
            own.extend(portless);
        }
        let origins: BTreeSet<String> = extra_origins
            .iter()
            .filter_map(|o| parse_origin(o).ok())
            .collect();
        let mut hosts = own.clone();
        hosts.extend(
            origins
                .iter()
                .filter_map(|o| o.split_once("://").map(|(_, a)| a.to_string())),
        );
        Self {
            hosts,
            own_hosts: own,
            origins,
            any_ip_at: bound.ip().is_unspecified().then_some(port),
        }
    }

    fn ip_literal_at_port(&self, host: &str) -> bool {
        self.any_ip_at
            .is_some_and(|port| host.parse::<SocketAddr>().is_ok_and(|a| a.port() == port))
    }

    /// A request's `Host` header.
    pub(crate) fn host(&self, host: &str) -> bool {
        let host = host.to_ascii_lowercase();
        self.hosts.contains(&host) || self.ip_literal_at_port(&host)
    }

    /// A request's `Origin` header: the console's own page, or an allowed origin.
    pub(crate) fn origin(&self, origin: &str) -> bool {
        let origin = origin.to_ascii_lowercase();
        if self.origins.contains(&origin) {
            return true;
        }
        origin
            .strip_prefix("http://")
            .is_some_and(|h| self.own_hosts.contains(h) || self.ip_literal_at_port(h))
    }
}

/// Failed authentication attempts per peer address (IPv6 per /64, since one host commonly
/// holds a whole /64) within a fixed window.
#[derive(Debug)]
pub(crate) struct AuthLimiter {
    max_failures: u32,
    window: Duration,
    peers: Mutex<HashMap<IpAddr, (Instant, u32)>>,
}

impl AuthLimiter {
    pub(crate) fn new(max_failures: u32, window: Duration) -> Self {
        Self {
            max_failures,
            window,
            peers: Mutex::new(HashMap::new()),
        }
    }

    fn key(ip: IpAddr) -> IpAddr {
        match ip {
            IpAddr::V6(v6) => match v6.to_ipv4_mapped() {
                Some(v4) => IpAddr::V4(v4),
                None => {
                    let s = v6.segments();
                    IpAddr::V6(Ipv6Addr::new(s[0], s[1], s[2], s[3], 0, 0, 0, 0))
                }
            },
            v4 => v4,
        }
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, HashMap<IpAddr, (Instant, u32)>> {
        self.peers.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// How long `ip` must still wait when it has used up its failures.
    pub(crate) fn blocked(&self, ip: IpAddr) -> Option<Duration> {
        let now = Instant::now();
        let peers = self.lock();
        let (since, failures) = peers.get(&Self::key(ip))?;
        let left = self.window.checked_sub(now.duration_since(*since))?;
        (*failures >= self.max_failures && !left.is_zero()).then_some(left)
    }

    /// Counts one failed attempt from `ip`.
    pub(crate) fn failed(&self, ip: IpAddr) {
        let now = Instant::now();
        let window = self.window;
        let mut peers = self.lock();
        if peers.len() >= 4096 {
            peers.retain(|_, (since, _)| now.duration_since(*since) < window);
        }
        let entry = peers.entry(Self::key(ip)).or_insert((now, 0));
        if now.duration_since(entry.0) >= window {
            *entry = (now, 0);
        }
        entry.1 = entry.1.saturating_add(1);
    }
}

/// A TCP listener that hands on at most `slots` connections at once.
pub(crate) struct CappedListener {
    tcp: TcpListener,
    slots: Arc<Semaphore>,
    refusing: Arc<Semaphore>,
    http_deadline: Duration,
}

impl CappedListener {
    pub(crate) fn new(tcp: TcpListener, max_connections: usize, http_deadline: Duration) -> Self {
        Self {
            tcp,
            slots: Arc::new(Semaphore::new(max_connections)),
            refusing: Arc::new(Semaphore::new(REFUSING_AT_ONCE)),
            http_deadline,
        }
    }
}

impl Listener for CappedListener {
    type Io = Conn;
    type Addr = SocketAddr;

    async fn accept(&mut self) -> (Conn, SocketAddr) {
        loop {
            let (tcp, addr) = match self.tcp.accept().await {
                Ok(accepted) => accepted,
                Err(e) => {
                    // Out of file descriptors and the like: wait rather than spin.
                    if !matches!(
                        e.kind(),
                        io::ErrorKind::ConnectionRefused
                            | io::ErrorKind::ConnectionAborted
                            | io::ErrorKind::ConnectionReset
                    ) {
                        tokio::time::sleep(Duration::from_millis(100)).await;
                    }
                    continue;
                }
            };
            match self.slots.clone().try_acquire_owned() {
                Ok(slot) => {
                    let conn = Conn {
                        tcp,
                        deadline: Some(Box::pin(tokio::time::sleep(self.http_deadline))),
                        read_budget: HTTP_REQUEST_BYTES,
                        upgraded: Arc::new(AtomicBool::new(false)),
                        _slot: slot,
                    };
                    return (conn, addr);
                }
                Err(_) => {
                    if let Ok(permit) = self.refusing.clone().try_acquire_owned() {
                        tokio::spawn(refuse(tcp, permit));
                    }
                }
            }
        }
    }

    fn local_addr(&self) -> io::Result<SocketAddr> {
        self.tcp.local_addr()
    }
}

/// Answers 503 to a connection beyond the cap: reads its request head first (at most 4 KiB or
/// 1 s) so that closing does not reset the connection before the client reads the answer.
async fn refuse(mut tcp: TcpStream, _permit: OwnedSemaphorePermit) {
    let second = Duration::from_secs(1);
    let mut head = vec![0u8; 4096];
    let mut seen = 0;
    let _ = tokio::time::timeout(second, async {
        while seen < head.len() {
            match tcp.read(&mut head[seen..]).await {
                Ok(0) | Err(_) => break,
                Ok(n) => seen += n,
            }
            if head[..seen].windows(4).any(|w| w == b"\r\n\r\n") {
                break;
            }
        }
    })
    .await;
    let body = "the console is serving its maximum number of connections; try again later\n";
    let reply = format!(
        "HTTP/1.1 503 Service Unavailable\r\nContent-Type: text/plain; charset=utf-8\r\n\
         Content-Length: {}\r\nRetry-After: 5\r\nConnection: close\r\n\r\n{body}",
        body.len()
    );
    let _ = tokio::time::timeout(second, async {
        let _ = tcp.write_all(reply.as_bytes()).await;
        let _ = tcp.shutdown().await;
        while let Ok(n) = tcp.read(&mut head).await {
            if n == 0 {
                break;
            }
        }
    })
    .await;
}

/// One accepted connection holding its slot until it is dropped. Until it is upgraded to a
/// WebSocket it may send at most [`HTTP_REQUEST_BYTES`] and lasts at most the HTTP deadline.
pub(crate) struct Conn {
    tcp: TcpStream,
    deadline: Option<Pin<Box<Sleep>>>,
    read_budget: usize,
    upgraded: Arc<AtomicBool>,
    _slot: OwnedSemaphorePermit,
}

impl Conn {
    /// Whether the connection has outlived its HTTP deadline (registers the waker if not).
    fn expired(&mut self, cx: &mut Context<'_>) -> bool {
        if self.upgraded.load(Ordering::Relaxed) {
            self.deadline = None;
            return false;
        }
        self.deadline
            .as_mut()
            .is_some_and(|d| d.as_mut().poll(cx).is_ready())
    }
}

fn timed_out() -> io::Error {
    io::Error::new(io::ErrorKind::TimedOut, "connection deadline passed")
}

impl AsyncRead for Conn {
    fn poll_read(
        self: Pin<&mut Self>,
        cx: &mut Context<'_>,
        buf: &mut ReadBuf<'_>,
    ) -> Poll<io::Result<()>> {
        let this = self.get_mut();
        if this.expired(cx) {
            return Poll::Ready(Err(timed_out()));
        }
        let before = buf.filled().len();
        let polled = Pin::new(&mut this.tcp).poll_read(cx, buf);
        if this.deadline.is_some() {
            let n = buf.filled().len() - before;
            this.read_budget = this.read_budget.saturating_sub(n);
            if this.read_budget == 0 {
                return Poll::Ready(Err(io::Error::new(
                    io::ErrorKind::InvalidData,
                    "request too large",
                )));
            }
        }
        polled
    }
}

impl AsyncWrite for Conn {
    fn poll_write(
        self: Pin<&mut Self>,
        cx: &mut Context<'_>,
        data: &[u8],
    ) -> Poll<io::Result<usize>> {
        let this = self.get_mut();
        if this.expired(cx) {
            return Poll::Ready(Err(timed_out()));
        }
        Pin::new(&mut this.tcp).poll_write(cx, data)
    }

    fn poll_write_vectored(
        self: Pin<&mut Self>,
        cx: &mut Context<'_>,
        bufs: &[io::IoSlice<'_>],
    ) -> Poll<io::Result<usize>> {
        let this = self.get_mut();
        if this.expired(cx) {
            return Poll::Ready(Err(timed_out()));
        }
        Pin::new(&mut this.tcp).poll_write_vectored(cx, bufs)
    }

    fn is_write_vectored(&self) -> bool {
        self.tcp.is_write_vectored()
    }

    fn poll_flush(self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<io::Result<()>> {
        let this = self.get_mut();
        if this.expired(cx) {
            return Poll::Ready(Err(timed_out()));
        }
        Pin::new(&mut this.tcp).poll_flush(cx)
    }

    fn poll_shutdown(self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<io::Result<()>> {
        Pin::new(&mut self.get_mut().tcp).poll_shutdown(cx)
    }
}

/// What a request knows of its connection: the peer's address, and the switch that exempts an
/// upgraded WebSocket from the HTTP deadline and size budget.
#[derive(Clone, Debug)]
pub(crate) struct Peer {
    pub(crate) addr: SocketAddr,
    upgraded: Arc<AtomicBool>,
}

impl Peer {
    /// The connection becomes a WebSocket (which has deadlines of its own).
    pub(crate) fn upgrading(&self) {
        self.upgraded.store(true, Ordering::Relaxed);
    }
}

impl Connected<IncomingStream<'_, CappedListener>> for Peer {
    fn connect_info(stream: IncomingStream<'_, CappedListener>) -> Self {
        Peer {
            addr: *stream.remote_addr(),
            upgraded: stream.io().upgraded.clone(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn origins_are_scheme_host_and_port_only() {
        assert_eq!(
            parse_origin("HTTPS://Console.Example.org"),
            Ok("https://console.example.org".into())
        );
        assert!(parse_origin("http://[::1]:8080").is_ok());
        for bad in [
            "console.example.org",
            "ftp://x",
            "https://x/",
            "https://x/path",
            "https://x:99999",
            "https://u@x",
            "https://",
        ] {
            assert!(parse_origin(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn loopback_allows_its_names_and_the_extra_origins_only() {
        let a = Allowed::new(
            "127.0.0.1:8080".parse().unwrap(),
            &["https://console.example.org".into()],
        );
        for host in [
            "127.0.0.1:8080",
            "localhost:8080",
            "LOCALHOST:8080",
            "[::1]:8080",
        ] {
            assert!(a.host(host), "{host}");
            assert!(a.origin(&format!("http://{host}")), "{host}");
        }
        assert!(a.host("console.example.org"));
        assert!(a.origin("https://console.example.org"));
        assert!(!a.origin("http://console.example.org"));
        for foreign in [
            "attacker.example",
            "localhost:8081",
            "127.0.0.1",
            "10.0.0.1:8080",
        ] {
            assert!(!a.host(foreign), "{foreign}");
        }
        assert!(!a.origin("http://evil.example"));
        assert!(!a.origin("null"));
    }

    #[test]
    fn a_wildcard_bind_allows_addresses_at_its_port_but_no_names() {
        let a = Allowed::new("0.0.0.0:8080".parse().unwrap(), &[]);
        assert!(a.host("192.168.1.5:8080"));
        assert!(a.origin("http://192.168.1.5:8080"));
        assert!(!a.host("192.168.1.5:8081"));
        assert!(!a.host("rebind.attacker.example:8080"));
        assert!(!a.host("localhost:8080"));
    }

    #[test]
    fn failures_block_a_peer_until_the_window_passes() {
        let limiter = AuthLimiter::new(2, Duration::from_secs(60));
        let ip: IpAddr = "2001:db8::1".parse().unwrap();
        limiter.failed(ip);
        assert!(limiter.blocked(ip).is_none());
        limiter.failed("2001:db8::2".parse().unwrap());
        assert!(limiter.blocked(ip).is_some(), "same /64");
        assert!(limiter.blocked("2001:db9::1".parse().unwrap()).is_none());
        let short = AuthLimiter::new(1, Duration::from_millis(1));
        short.failed(ip);
        std::thread::sleep(Duration::from_millis(5));
        assert!(short.blocked(ip).is_none());
    }
}
