//! Connections and requests: the listener (plain or TLS), bounded in connections at once and in
//! the time a request's head, a TLS handshake or a body may take, so that a slow or stuck
//! client holds only its own connection; the token; and the routes.

use std::convert::Infallible;
use std::net::SocketAddr;
use std::sync::Arc;
use std::time::Duration;

use hyper::body::Incoming;
use hyper::{Method, Request, Response, StatusCode};
use hyper_util::rt::{TokioIo, TokioTimer};
use tokio::io::{AsyncRead, AsyncWrite};
use tokio::net::TcpListener;
use tokio_rustls::TlsAcceptor;

use crate::serve::sessions::registry::Registry;
use crate::serve::http::respond::{full, log, refused, Body};
use crate::serve::app::State;
use crate::serve::http::static_files::StaticRoots;
use crate::serve::http::{banner as token, tls};
use crate::serve::sessions::routes as api;
use crate::serve::{ids, Refusal, ServeConfig, ServeError};

/// Runs the server (see [`crate::serve::run`]) until Ctrl-C or SIGTERM, then flushes every open file
/// and writes `sessions.json`; open sessions stay open, to be continued when it starts again.
pub async fn serve(config: ServeConfig) -> Result<(), ServeError> {
    let (registry, notes) = Registry::load(&config.out, config.banks.clone(), config.max_sessions)?;
    for n in notes {
        log(&n);
    }
    for e in registry.unverified_ended() {
        api::verify_again(&registry, &e).await;
    }
    let participants = match &config.protocol {
        None => None,
        Some(loaded) => {
            let (p, notes) = crate::serve::protocol::participants::Participants::open(loaded.clone(), &config.out).map_err(|message| ServeError::Io { path: config.out.display().to_string(), message })?;
            log(&format!("protocol {}: {} participants, {} conditions; the participant's page is /protocol, the researcher's /dashboard", loaded.protocol.name, loaded.protocol.participants, loaded.protocol.conditions.len()));
            for n in notes {
                log(&n);
            }
            Some(Arc::new(p))
        }
    };
    let needs_token = config.require_token || !config.host.is_loopback();
    let token = if needs_token { Some(ids::random_hex(16)?) } else { None };
    let shown_host = token::shown_host(config.host);
    let acceptor = tls::acceptor(&config.tls, &config.out, &shown_host)?.map(TlsAcceptor::from);
    let listener = TcpListener::bind((config.host, config.port)).await.map_err(|e| ServeError::Bind { addr: format!("{}:{}", config.host, config.port), message: e.to_string() })?;
    let addr = listener.local_addr().map_err(|e| ServeError::Bind { addr: config.host.to_string(), message: e.to_string() })?;
    let statics = StaticRoots::new(&config.web, &config.assets, &config.wasm, &config.banks);
    let state = Arc::new(State {
        registry,
        token: token.clone(),
        statics,
        read_timeout: config.read_timeout,
        writer_lease: config.writer_lease,
        tls: acceptor.is_some(),
        verifying: tokio::sync::Semaphore::new(std::thread::available_parallelism().map_or(1, |n| n.get().saturating_sub(1).max(1))),
        participants,
        live: Default::default(),
    });

    let scheme = if acceptor.is_some() { "https" } else { "http" };
    let url = match &token {
        Some(t) => format!("{scheme}://{}/?token={t}", token::host_port(&shown_host, addr.port())),
        None => format!("{scheme}://{}/", token::host_port(&shown_host, addr.port())),
    };
    log(&format!("grove serve {}: sessions in {}", env!("CARGO_PKG_VERSION"), config.out.display()));
    log(&format!("listening on {url}"));
    if let Some(_t) = &token {
        log("every request needs this token (in the URL once, then a cookie; or 'Authorization: Bearer TOKEN'); scan to open it:");
        println!("{}", token::qr(&url));
    }

    let graceful = hyper_util::server::graceful::GracefulShutdown::new();
    let limit = Arc::new(tokio::sync::Semaphore::new(config.max_connections.max(1)));
    let abandon = tokio::spawn(api::abandon_loop(state.clone(), config.abandon_after));
    let mut stop = Box::pin(stop_signal());
    loop {
        let permit = tokio::select! {
            _ = &mut stop => break,
            p = limit.clone().acquire_owned() => match p { Ok(p) => p, Err(_) => break },
        };
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
        let _ = stream.set_nodelay(true);
        let state = state.clone();
        let acceptor = acceptor.clone();
        let watcher = graceful.watcher();
        tokio::spawn(async move {
            let _permit = permit;
            match acceptor {
                None => connection(state, stream, peer, watcher).await,
                Some(acc) => {
                    // A handshake that fails or does not finish in time ends the connection.
                    if let Ok(Ok(tls_stream)) = tokio::time::timeout(state.read_timeout, acc.accept(stream)).await {
                        connection(state, tls_stream, peer, watcher).await;
                    }
                }
            }
        });
    }
    abandon.abort();
    log("stopping: finishing the requests in progress");
    let _ = tokio::time::timeout(Duration::from_secs(3), graceful.shutdown()).await;
    let open = api::flush_all(&state).await;
    state.registry.save()?;
    log(&format!("stopped; {open} sessions left open in {} (continued when grove serve starts again on it)", config.out.display()));
    Ok(())
}

/// Serves one connection's requests (HTTP/1.1, keep-alive) until it closes.
async fn connection<I: AsyncRead + AsyncWrite + Unpin + Send + 'static>(state: Arc<State>, io: I, _peer: SocketAddr, watcher: hyper_util::server::graceful::Watcher) {
    let read_timeout = state.read_timeout;
    let service = hyper::service::service_fn(move |req| {
        let state = state.clone();
        async move { Ok::<_, Infallible>(route(state, req).await) }
    });
    let mut builder = hyper::server::conn::http1::Builder::new();
    builder.timer(TokioTimer::new()).header_read_timeout(Some(read_timeout)).keep_alive(true).half_close(true);
    let conn = builder.serve_connection(TokioIo::new(io), service);
    let _ = watcher.watch(conn).await;
}

/// Waits for Ctrl-C or SIGTERM.
async fn stop_signal() {
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

/// The token a request carries: `?token=` in its URL, `Authorization: Bearer`, or the cookie
/// `grove_token`; and whether it came in the URL.
fn carried_token(req: &Request<Incoming>) -> (Option<String>, bool) {
    if let Some(q) = req.uri().query() {
        for pair in q.split('&') {
            if let Some(v) = pair.strip_prefix("token=") {
                return (Some(v.to_string()), true);
            }
        }
    }
    if let Some(v) = req.headers().get(hyper::header::AUTHORIZATION).and_then(|v| v.to_str().ok())
        && let Some(t) = v.strip_prefix("Bearer ")
    {
        return (Some(t.trim().to_string()), false);
    }
    for v in req.headers().get_all(hyper::header::COOKIE) {
        if let Ok(s) = v.to_str() {
            for c in s.split(';') {
                if let Some(t) = c.trim().strip_prefix("grove_token=") {
                    return (Some(t.to_string()), false);
                }
            }
        }
    }
    (None, false)
}

/// Routes a request: the token first, then the session API, then static files.
async fn route(state: Arc<State>, req: Request<Incoming>) -> Response<Body> {
    let mut set_cookie = None;
    if let Some(expected) = &state.token {
        let (given, in_url) = carried_token(&req);
        match given {
            Some(t) if ids::same_secret(&t, expected) => {
                if in_url {
                    let secure = if state.tls { "; Secure" } else { "" };
                    set_cookie = Some(format!("grove_token={expected}; Path=/; HttpOnly; SameSite=Strict{secure}"));
                }
            }
            _ => {
                let mut r = Response::new(full("a session token is needed: open the URL grove serve printed (or send 'Authorization: Bearer TOKEN')\n"));
                *r.status_mut() = StatusCode::UNAUTHORIZED;
                return r;
            }
        }
    }
    let path = req.uri().path().to_string();
    let mut response = if crate::serve::protocol::routes::is_protocol_path(&path) {
        crate::serve::protocol::routes::route(&state, req).await
    } else if path == "/api" || path.starts_with("/api/") {
        api::route(&state, req).await
    } else if req.method() == Method::GET || req.method() == Method::HEAD {
        let head = req.method() == Method::HEAD;
        if path == "/" && !state.statics.has_page() {
            api::index_page(&state)
        } else {
            match state.statics.serve(&path, head).await {
                Ok(r) => r,
                Err(r) => refused(&r, serde_json::json!({})),
            }
        }
    } else {
        refused(&Refusal::method(format!("{} is not served here; files take GET", req.method())), serde_json::json!({}))
    };
    if let Some(c) = set_cookie
        && let Ok(v) = hyper::header::HeaderValue::from_str(&c)
    {
        response.headers_mut().insert(hyper::header::SET_COOKIE, v);
    }
    response
}
