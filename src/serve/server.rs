//! `grove serve` from start to stop: the sessions' folder read back (its open sessions continued,
//! its unverified ones verified), the protocol's participants, the token (kept in the folder),
//! TLS, the listener and
//! the banner; then requests until Ctrl-C or SIGTERM; then every open file flushed and
//! `sessions.json` written, the open sessions left open to be continued at the next start.

use std::sync::Arc;

use tokio_rustls::TlsAcceptor;

use crate::serve::app::App;
use crate::serve::config::ServeConfig;
use crate::serve::error::ServeError;
use crate::serve::http::listen::{bind, serve_until, stop_signal, Limits};
use crate::serve::http::static_files::StaticRoots;
use crate::serve::http::token::{Kept, Token, TOKEN_FILE};
use crate::serve::http::{banner, tls};
use crate::serve::log::log;
use crate::serve::protocol::participants::Participants;
use crate::serve::protocol::Protocol;
use crate::serve::sessions::jobs::abandon_loop;
use crate::serve::sessions::service::Sessions;

/// Runs the server until Ctrl-C (or SIGTERM).
pub fn run(config: ServeConfig) -> Result<(), ServeError> {
    let runtime = tokio::runtime::Builder::new_multi_thread().enable_all().build().map_err(|e| ServeError::Runtime(e.to_string()))?;
    runtime.block_on(serve(config))
}

/// Runs the server until Ctrl-C or SIGTERM, then flushes every open file and writes
/// `sessions.json`; open sessions stay open, to be continued when it starts again.
pub async fn serve(config: ServeConfig) -> Result<(), ServeError> {
    let (sessions, notes) = Sessions::load(&config.out, config.banks.clone(), config.max_sessions, config.read_timeout, config.writer_lease, config.live)?;
    for n in notes {
        log(&n);
    }
    let sessions = Arc::new(sessions);
    sessions.verify_unverified().await;
    let protocol = match &config.protocol {
        None => None,
        Some(loaded) => {
            let (participants, notes) = Participants::open(loaded.clone(), &config.out).map_err(|source| ServeError::Protocol { path: config.out.display().to_string(), source })?;
            log(&format!("protocol {}: {} participants, {} conditions; the participant's page is /protocol, the researcher's /dashboard", loaded.protocol.name, loaded.protocol.participants, loaded.protocol.conditions.len()));
            for n in notes {
                log(&n);
            }
            Some(Protocol { participants, sessions: sessions.clone() })
        }
    };
    let shown_host = banner::shown_host(config.host);
    let acceptor = tls::acceptor(&config.tls, &config.out, &shown_host)?.map(TlsAcceptor::from);
    let needs_token = config.require_token || !config.host.is_loopback();
    let token = match needs_token {
        false => None,
        true => Some(Token::kept(&config.out, acceptor.is_some(), config.new_token)?),
    };
    let (listener, addr) = bind(config.host, config.port).await?;
    let url = banner::url(acceptor.is_some(), &shown_host, addr.port(), token.as_ref().map(|(t, _)| t.secret()));
    log(&format!("grove serve {}: sessions in {}", env!("CARGO_PKG_VERSION"), config.out.display()));
    log(&format!("listening on {url}"));
    if let Some((_, kept)) = &token {
        let file = config.out.join(TOKEN_FILE);
        log(&match kept {
            Kept::Read => format!("the token is the one kept in {} (clients that had it go on; --new-token draws another)", file.display()),
            Kept::Drawn => format!("a new token, kept in {} for the next start on this folder", file.display()),
        });
        log("every request needs this token (in the URL once, then a cookie; or 'Authorization: Bearer TOKEN'); scan to open it:");
        println!("{}", banner::qr(&url));
    }

    let app = Arc::new(App { sessions: sessions.clone(), protocol, statics: StaticRoots::new(&config.web, &config.assets, &config.wasm, &config.banks), tls: acceptor.is_some() });
    let abandon = tokio::spawn(abandon_loop(sessions.clone(), config.abandon_after));
    let limits = Limits { read_timeout: config.read_timeout, max_connections: config.max_connections, max_per_address: config.max_per_address };
    serve_until(listener, acceptor, token.map(|(t, _)| t), &limits, app, stop_signal()).await;
    abandon.abort();
    let open = sessions.flush_all().await;
    sessions.registry.save()?;
    log(&format!("stopped; {open} sessions left open in {} (continued when grove serve starts again on it)", config.out.display()));
    Ok(())
}
