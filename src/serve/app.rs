//! The server's own routes and where every request goes (after the token, checked beneath):
//! the protocol's paths to the protocol (404 when none runs), `/api/sessions…` to the sessions,
//! `/api/status` and `/api/index` answered here, any other `/api/…` path refused as every router
//! refuses it, and everything else to the files (or, without a built page, the server's own
//! page at `/`).

use std::sync::Arc;

use hyper::body::Incoming;
use hyper::{Method, Request, Response};
use serde_json::json;

use crate::serve::http::listen::Handler;
use crate::serve::http::respond::{json, refused, Body};
use crate::serve::http::router::{find, Route};
use crate::serve::http::static_files::StaticRoots;
use crate::serve::index_page;
use crate::serve::protocol::routes as protocol_routes;
use crate::serve::protocol::Protocol;
use crate::serve::sessions::routes as session_routes;
use crate::serve::sessions::service::Sessions;

/// What every request sees.
pub struct App {
    /// The sessions.
    pub sessions: Arc<Sessions>,
    /// The protocol, when the server runs one.
    pub protocol: Option<Protocol>,
    /// The folders served as they are.
    pub statics: StaticRoots,
    /// Whether connections are TLS.
    pub tls: bool,
}

impl Handler for App {
    async fn handle(self: Arc<Self>, req: Request<Incoming>) -> Response<Body> {
        self.route(req).await
    }
}

#[derive(Clone, Copy)]
enum To {
    Status,
    Index,
}

impl App {
    /// Where a request goes.
    async fn route(&self, req: Request<Incoming>) -> Response<Body> {
        let path = req.uri().path().to_string();
        if protocol_routes::serves(&path) {
            protocol_routes::route(self.protocol.as_ref(), req).await
        } else if session_routes::serves(&path) {
            session_routes::route(&self.sessions, req).await
        } else if path == "/api" || path.starts_with("/api/") {
            let routes = [Route { method: Method::GET, path: "/api/status", to: To::Status }, Route { method: Method::GET, path: "/api/index", to: To::Index }];
            match find(&routes, req.method(), &path) {
                Ok((To::Status, _)) => self.status(),
                Ok((To::Index, _)) => json(200, &self.statics.index()),
                Err(miss) => refused(&miss),
            }
        } else if path == "/" && (req.method() == Method::GET || req.method() == Method::HEAD) && !self.statics.has_page() {
            index_page::page(&self.sessions.registry.entries(), &self.statics.index())
        } else {
            self.statics.answer(req.method(), &path).await.unwrap_or_else(|r| refused(&r))
        }
    }

    /// `/api/status`: the server, its open sessions, TLS, and the name of the protocol it runs
    /// (the headset page then follows it) or null.
    fn status(&self) -> Response<Body> {
        let protocol = self.protocol.as_ref().map(|p| p.participants.loaded.protocol.name.clone());
        json(200, &json!({ "server": "grove serve", "version": env!("CARGO_PKG_VERSION"), "open_sessions": self.sessions.registry.open_sessions().len(), "tls": self.tls, "protocol": protocol }))
    }
}
