//! The token: 128 random bits, drawn once for a folder and kept in `DIR/token` (readable by its
//! owner only, as the TLS key is), so that a server started again on the folder after a crash
//! has the same one and every client (a headset's cookie, `grove serve push`'s URL) goes on;
//! `--new-token` draws another. It is checked on every request before anything else. A client
//! carries it in the URL once (`?token=`; the answer then sets the cookie `grove_token`), as
//! `Authorization: Bearer TOKEN`, or in that cookie (`docs/serve.md`, "The token"). Without it
//! a request gets 401, a JSON refusal like every other, and nothing else.

use std::path::Path;

use hyper::header::{HeaderValue, AUTHORIZATION, COOKIE, WWW_AUTHENTICATE};
use hyper::{Request, Response};

use crate::serve::http::error::HttpError;
use crate::serve::http::refusal::Refusal;
use crate::serve::http::respond::{refused, Body};
use crate::serve::ids::{random_hex, same_secret};

/// The file of a folder that keeps its token.
pub const TOKEN_FILE: &str = "token";

/// Where a folder's token came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kept {
    /// Read from `DIR/token`: the token of the server's last start on the folder.
    Read,
    /// Drawn now (no token kept yet, or `--new-token`) and written to `DIR/token`.
    Drawn,
}

/// The token every request must carry.
pub struct Token {
    secret: String,
    /// Whether connections are TLS (the cookie is then `Secure`).
    tls: bool,
}

impl Token {
    /// The token kept in `dir/token`, or (when there is none, or `renew`) a new random one,
    /// written there before it is used.
    pub fn kept(dir: &Path, tls: bool, renew: bool) -> Result<(Token, Kept), HttpError> {
        let path = dir.join(TOKEN_FILE);
        let shown = path.display().to_string();
        if !renew && path.exists() {
            let text = grove_systems::files::read_text(&path, grove_systems::files::Kind::Index).map_err(|e| HttpError::Io { path: shown.clone(), message: e.reason() })?;
            let secret = text.trim_end_matches('\n');
            if !crate::serve::ids::is_secret(secret) {
                return Err(HttpError::Io { path: shown, message: "not a token (32 lowercase hex digits on one line); start the server with --new-token to draw another".into() });
            }
            return Ok((Token { secret: secret.to_string(), tls }, Kept::Read));
        }
        let secret = random_hex(16)?;
        std::fs::create_dir_all(dir).map_err(|e| HttpError::Io { path: dir.display().to_string(), message: e.to_string() })?;
        crate::atomic_write::write_private(&path, format!("{secret}\n").as_bytes()).map_err(|e| HttpError::Io { path: shown, message: e.source.to_string() })?;
        Ok((Token { secret, tls }, Kept::Drawn))
    }

    /// The token itself, for the URL printed at start.
    pub fn secret(&self) -> &str {
        &self.secret
    }

    /// Checks the token `req` carries: the cookie to set on its answer when it came in the URL,
    /// or the refusal to send.
    pub fn check<B>(&self, req: &Request<B>) -> Result<Option<HeaderValue>, Response<Body>> {
        match carried(req) {
            (Some(t), in_url) if same_secret(&t, &self.secret) => {
                let secure = if self.tls { "; Secure" } else { "" };
                Ok(in_url.then(|| HeaderValue::from_str(&format!("grove_token={}; Path=/; HttpOnly; SameSite=Strict{secure}", self.secret)).ok()).flatten())
            }
            _ => {
                let mut r = refused(&Refusal::new(401, "a session token is needed: open the URL grove serve printed (or send 'Authorization: Bearer TOKEN')"));
                r.headers_mut().insert(WWW_AUTHENTICATE, HeaderValue::from_static("Bearer realm=\"grove serve\""));
                Err(r)
            }
        }
    }
}

/// The token a request carries: `?token=` in its URL, `Authorization: Bearer`, or the cookie
/// `grove_token`; and whether it came in the URL.
fn carried<B>(req: &Request<B>) -> (Option<String>, bool) {
    if let Some(q) = req.uri().query() {
        for pair in q.split('&') {
            if let Some(v) = pair.strip_prefix("token=") {
                return (Some(v.to_string()), true);
            }
        }
    }
    if let Some(v) = req.headers().get(AUTHORIZATION).and_then(|v| v.to_str().ok())
        && let Some(t) = v.strip_prefix("Bearer ")
    {
        return (Some(t.trim().to_string()), false);
    }
    for v in req.headers().get_all(COOKIE) {
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
