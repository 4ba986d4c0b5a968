//! Connections: the listener (plain or TLS), bounded in connections at once, in all and per
//! address, the idle ones closed first where a limit is reached (`pool.rs`), and in the time a
//! request's head, a TLS handshake or a body may take, so that a slow, stuck or idle client holds
//! only its own connection; the token checked before a request reaches its handler; a clean stop
//! on Ctrl-C or SIGTERM.

use std::convert::Infallible;
use std::future::Future;
use std::net::{IpAddr, SocketAddr};
use std::sync::Arc;
use std::time::Duration;

use http_body_util::BodyExt;
use hyper::body::Incoming;
use hyper::header::SET_COOKIE;
use hyper::{Request, Response};
use hyper_util::rt::{TokioIo, TokioTimer};
use hyper_util::server::graceful::{GracefulShutdown, Watcher};
use tokio::io::{AsyncRead, AsyncWrite};
use tokio::net::TcpListener;
use tokio_rustls::TlsAcceptor;

use crate::serve::http::error::HttpError;
use crate::serve::http::pool::{Busy, Pool, Ticket};
use crate::serve::http::respond::Body;
use crate::serve::http::token::Token;
use crate::serve::log::log;

/// What answers the requests that carry the token.
pub trait Handler: Send + Sync + 'static {
    /// The answer to one request.
    fn handle(self: Arc<Self>, req: Request<Incoming>) -> impl Future<Output = Response<Body>> + Send;
}

/// How connections are taken.
pub struct Limits {
    /// The longest a request's head or a TLS handshake may take to arrive.
    pub read_timeout: Duration,
    /// The most connections served at once (the idle one longest closes for a new one; while all
    /// are busy, more wait to be accepted).
    pub max_connections: usize,
    /// The most connections from one address (the idle one longest closes for a new one; while
    /// all are busy, a new one is closed at once).
    pub max_per_address: usize,
}

/// Listens on `host:port` (port 0: any free one); returns the listener and its address.
pub async fn bind(host: IpAddr, port: u16) -> Result<(TcpListener, SocketAddr), HttpError> {
    let listener = TcpListener::bind((host, port)).await.map_err(|e| HttpError::Bind { addr: format!("{host}:{port}"), message: e.to_string() })?;
    let addr = listener.local_addr().map_err(|e| HttpError::Bind { addr: host.to_string(), message: e.to_string() })?;
    Ok((listener, addr))
}

/// Serves connections until `stop` fires, then lets the requests in progress finish (3 s at
/// most). Every request must carry `token`, if there is one, before `handler` sees it.
pub async fn serve_until<H: Handler>(listener: TcpListener, acceptor: Option<TlsAcceptor>, token: Option<Token>, limits: &Limits, handler: Arc<H>, stop: impl Future<Output = ()>) {
    let graceful = GracefulShutdown::new();
    let token = token.map(Arc::new);
    let pool = Pool::new(limits.max_connections, limits.max_per_address);
    let read_timeout = limits.read_timeout;
    let mut stop = std::pin::pin!(stop);
    loop {
        let (stream, peer) = tokio::select! {
            _ = &mut stop => break,
            a = listener.accept() => match a {
                Ok(a) => a,
                Err(e) => {
                    log(&format!("accept failed: {e}"));
                    tokio::time::sleep(Duration::from_millis(50)).await;
                    continue;
                }
            },
        };
        let ticket = tokio::select! {
            _ = &mut stop => break,
            t = pool.admit(peer.ip()) => match t {
                Some(t) => t,
                // Every connection of that address is busy: this one is closed at once.
                None => continue,
            },
        };
        let _ = stream.set_nodelay(true);
        let (handler, token, acceptor, watcher) = (handler.clone(), token.clone(), acceptor.clone(), graceful.watcher());
        tokio::spawn(async move {
            let ticket = Arc::new(ticket);
            match acceptor {
                None => connection(handler, token, read_timeout, stream, watcher, ticket).await,
                Some(acc) => {
                    // A handshake that fails, does not finish in time or is closed for another
                    // connection ends the connection.
                    let handshake = tokio::select! {
                        h = tokio::time::timeout(read_timeout, acc.accept(stream)) => h,
                        _ = ticket.closed() => return,
                    };
                    if let Ok(Ok(tls_stream)) = handshake {
                        connection(handler, token, read_timeout, tls_stream, watcher, ticket).await;
                    }
                }
            }
        });
    }
    log("stopping: finishing the requests in progress");
    let _ = tokio::time::timeout(Duration::from_secs(3), graceful.shutdown()).await;
}

/// Serves one connection's requests (HTTP/1.1, keep-alive) until it closes, or until the pool
/// closes it for another connection: at once when no request is in progress, else once the
/// request's answer has been sent.
async fn connection<H: Handler, I: AsyncRead + AsyncWrite + Unpin + Send + 'static>(handler: Arc<H>, token: Option<Arc<Token>>, read_timeout: Duration, io: I, watcher: Watcher, ticket: Arc<Ticket>) {
    let seen = ticket.clone();
    let service = hyper::service::service_fn(move |req| {
        let (handler, token, busy) = (handler.clone(), token.clone(), seen.busy());
        async move {
            let response = checked(handler, token.as_deref(), req).await;
            // Busy until the answer's body has been sent (or dropped).
            Ok::<_, Infallible>(response.map(|body| Held { body, _busy: busy }.boxed()))
        }
    });
    let mut builder = hyper::server::conn::http1::Builder::new();
    builder.timer(TokioTimer::new()).header_read_timeout(Some(read_timeout)).keep_alive(true).half_close(true);
    let conn = watcher.watch(builder.serve_connection(TokioIo::new(io), service));
    let mut conn = std::pin::pin!(conn);
    tokio::select! {
        _ = &mut conn => return,
        _ = ticket.closed() => {}
    }
    while ticket.is_busy() {
        tokio::select! {
            _ = &mut conn => return,
            _ = tokio::time::sleep(Duration::from_millis(10)) => {}
        }
    }
}

/// A response body that keeps its connection busy until it has been sent (or dropped), and is
/// otherwise the body it holds (its length included, sent as Content-Length).
struct Held {
    body: Body,
    _busy: Busy,
}

impl hyper::body::Body for Held {
    type Data = bytes::Bytes;
    type Error = std::io::Error;

    fn poll_frame(mut self: std::pin::Pin<&mut Self>, cx: &mut std::task::Context<'_>) -> std::task::Poll<Option<Result<hyper::body::Frame<bytes::Bytes>, std::io::Error>>> {
        std::pin::Pin::new(&mut self.body).poll_frame(cx)
    }

    fn is_end_stream(&self) -> bool {
        self.body.is_end_stream()
    }

    fn size_hint(&self) -> hyper::body::SizeHint {
        self.body.size_hint()
    }
}

/// The token first (401 without it), then the handler; the token's cookie is set on the answer
/// to a request that carried it in its URL.
async fn checked<H: Handler>(handler: Arc<H>, token: Option<&Token>, req: Request<Incoming>) -> Response<Body> {
    let cookie = match token.map(|t| t.check(&req)) {
        None | Some(Ok(None)) => None,
        Some(Ok(Some(c))) => Some(c),
        Some(Err(refused)) => return refused,
    };
    let mut response = handler.handle(req).await;
    if let Some(c) = cookie {
        response.headers_mut().insert(SET_COOKIE, c);
    }
    response
}

/// Waits for Ctrl-C or SIGTERM.
pub async fn stop_signal() {
    #[cfg(unix)]
    {
        let mut term = match tokio::signal::unix::signal(tokio::signal::unix::SignalKind::terminate()) {
            Ok(t) => t,
            Err(_) => {
                let _ = tokio::signal::ctrl_c().await;
                return;
            }
        };
        tokio::select! {
            _ = tokio::signal::ctrl_c() => {}
            _ = term.recv() => {}
        }
    }
    #[cfg(not(unix))]
    {
        let _ = tokio::signal::ctrl_c().await;
    }
}
