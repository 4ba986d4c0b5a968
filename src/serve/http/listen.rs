//! Connections: the listener (plain or TLS), bounded in connections at once and in the time a
//! request's head, a TLS handshake or a body may take, so that a slow or stuck client holds only
//! its own connection; the token checked before a request reaches its handler; a clean stop on
//! Ctrl-C or SIGTERM.

use std::convert::Infallible;
use std::future::Future;
use std::net::{IpAddr, SocketAddr};
use std::sync::Arc;
use std::time::Duration;

use hyper::body::Incoming;
use hyper::header::SET_COOKIE;
use hyper::{Request, Response};
use hyper_util::rt::{TokioIo, TokioTimer};
use hyper_util::server::graceful::{GracefulShutdown, Watcher};
use tokio::io::{AsyncRead, AsyncWrite};
use tokio::net::TcpListener;
use tokio_rustls::TlsAcceptor;

use crate::serve::http::error::HttpError;
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
    /// The most connections served at once (more wait to be accepted).
    pub max_connections: usize,
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
    let limit = Arc::new(tokio::sync::Semaphore::new(limits.max_connections.max(1)));
    let read_timeout = limits.read_timeout;
    let mut stop = std::pin::pin!(stop);
    loop {
        let permit = tokio::select! {
            _ = &mut stop => break,
            p = limit.clone().acquire_owned() => match p { Ok(p) => p, Err(_) => break },
        };
        let (stream, _peer) = tokio::select! {
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
        let _ = stream.set_nodelay(true);
        let (handler, token, acceptor, watcher) = (handler.clone(), token.clone(), acceptor.clone(), graceful.watcher());
        tokio::spawn(async move {
            let _permit = permit;
            match acceptor {
                None => connection(handler, token, read_timeout, stream, watcher).await,
                Some(acc) => {
                    // A handshake that fails or does not finish in time ends the connection.
                    if let Ok(Ok(tls_stream)) = tokio::time::timeout(read_timeout, acc.accept(stream)).await {
                        connection(handler, token, read_timeout, tls_stream, watcher).await;
                    }
                }
            }
        });
    }
    log("stopping: finishing the requests in progress");
    let _ = tokio::time::timeout(Duration::from_secs(3), graceful.shutdown()).await;
}

/// Serves one connection's requests (HTTP/1.1, keep-alive) until it closes.
async fn connection<H: Handler, I: AsyncRead + AsyncWrite + Unpin + Send + 'static>(handler: Arc<H>, token: Option<Arc<Token>>, read_timeout: Duration, io: I, watcher: Watcher) {
    let service = hyper::service::service_fn(move |req| {
        let (handler, token) = (handler.clone(), token.clone());
        async move { Ok::<_, Infallible>(checked(handler, token.as_deref(), req).await) }
    });
    let mut builder = hyper::server::conn::http1::Builder::new();
    builder.timer(TokioTimer::new()).header_read_timeout(Some(read_timeout)).keep_alive(true).half_close(true);
    let conn = builder.serve_connection(TokioIo::new(io), service);
    let _ = watcher.watch(conn).await;
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
