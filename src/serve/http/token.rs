//! The token: made at start (128 random bits) where one is needed, and checked on every request
//! before anything else. A client carries it in the URL once (`?token=`; the answer then sets
//! the cookie `grove_token`), as `Authorization: Bearer TOKEN`, or in that cookie
//! (`docs/serve.md`, "The token"). Without it a request gets 401 and one line of text, nothing
//! else.

use hyper::header::{HeaderValue, AUTHORIZATION, COOKIE};
use hyper::{Request, Response, StatusCode};

use crate::serve::http::respond::{full, Body};
use crate::serve::ids::{random_hex, same_secret, IdError};

/// The token every request must carry.
pub struct Token {
    secret: String,
    /// Whether connections are TLS (the cookie is then `Secure`).
    tls: bool,
}

impl Token {
    /// A new random token.
    pub fn new(tls: bool) -> Result<Token, IdError> {
        Ok(Token { secret: random_hex(16)?, tls })
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
                let mut r = Response::new(full("a session token is needed: open the URL grove serve printed (or send 'Authorization: Bearer TOKEN')\n"));
                *r.status_mut() = StatusCode::UNAUTHORIZED;
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
