//! The one HTTP/1.1 client of the session server, for `grove serve push`, `grove serve bench`
//! and the tests: one keep-alive connection, plain or TLS (trusting the certificate given, as
//! `--tls auto` makes one), every request bounded in time, the token of the URL sent as
//! `Authorization: Bearer`.

use std::path::Path;
use std::sync::Arc;
use std::time::Duration;

use bytes::Bytes;
use http_body_util::{BodyExt, Full};
use hyper::client::conn::http1::SendRequest;
use hyper::header::{HeaderMap, HeaderName, HeaderValue, AUTHORIZATION, HOST};
use hyper::{Method, Request, Uri};
use hyper_util::rt::TokioIo;
use tokio::net::TcpStream;
use tokio_rustls::rustls;
use tokio_rustls::rustls::pki_types::ServerName;

use crate::serve::http::error::HttpError;
use crate::serve::http::tls;
use crate::serve::ids::{random_hex, IdError};

/// Why a client could not reach the server, or what the server refused; one line.
#[derive(Debug, thiserror::Error)]
pub enum ClientError {
    /// The URL is not one of a server.
    #[error("--to {url:?}: {why}")]
    Url {
        /// The URL given.
        url: String,
        /// Why.
        why: String,
    },
    /// The certificate to trust could not be read.
    #[error(transparent)]
    Tls(#[from] HttpError),
    /// No writer name could be made.
    #[error(transparent)]
    Random(#[from] IdError),
    /// The connection failed or broke (then open another).
    #[error("{0}")]
    Connection(String),
    /// No connection or no answer in time.
    #[error("{0} within {1:.1} s")]
    Late(String, f64),
    /// The server refused a request.
    #[error("{what} refused ({status}): {reason}")]
    Refused {
        /// What was refused.
        what: String,
        /// The HTTP status.
        status: u16,
        /// The server's reason.
        reason: String,
    },
    /// The server's answer lacks what the client needs.
    #[error("{0}")]
    Answer(String),
    /// The server could not be reached for too long.
    #[error("gave up after {seconds:.0} s without the server: {why}")]
    GaveUp {
        /// Seconds without the server.
        seconds: f64,
        /// The last failure.
        why: String,
    },
    /// A file the client reads, or a process it starts.
    #[error("{0}")]
    Local(String),
}

/// Where a server is, from a URL such as `http://host:port/?token=T`.
#[derive(Clone)]
pub struct Endpoint {
    host: String,
    port: u16,
    /// The token, if the URL has one.
    pub token: Option<String>,
    tls: Option<(tokio_rustls::TlsConnector, ServerName<'static>)>,
    /// The client's name for the server's writer check (`Grove-Writer`).
    pub writer: String,
}

/// An answer: the status and the JSON body (`null` when the body is not JSON).
pub type Answer = (u16, serde_json::Value);

/// A whole answer: status, headers and body.
pub struct Reply {
    /// The HTTP status.
    pub status: u16,
    /// The headers.
    pub headers: HeaderMap,
    /// The body.
    pub body: Bytes,
}

impl Reply {
    /// The body as JSON (`null` when it is not).
    pub fn json(&self) -> serde_json::Value {
        serde_json::from_slice(&self.body).unwrap_or(serde_json::Value::Null)
    }
}

impl Endpoint {
    /// Reads a URL; an `https` URL needs `ca`, the certificate (PEM) to trust.
    pub fn parse(url: &str, ca: Option<&Path>) -> Result<Endpoint, ClientError> {
        let bad = |why: &str| ClientError::Url { url: url.to_string(), why: why.to_string() };
        let uri: Uri = url.parse().map_err(|_| bad("not a URL such as http://192.168.1.5:8080/?token=…"))?;
        let https = match uri.scheme_str() {
            Some("http") => false,
            Some("https") => true,
            _ => return Err(bad("the URL must start with http:// or https://")),
        };
        let host = uri.host().ok_or_else(|| bad("the URL has no host"))?.trim_start_matches('[').trim_end_matches(']').to_string();
        let port = uri.port_u16().unwrap_or(if https { 443 } else { 80 });
        let token = uri.query().and_then(|q| q.split('&').find_map(|p| p.strip_prefix("token=")).map(str::to_string));
        let tls = if https {
            let ca = ca.ok_or_else(|| bad("an https URL needs --ca CERT.pem, the server's certificate (grove serve --tls auto writes it to DIR/tls/cert.pem)"))?;
            let mut roots = rustls::RootCertStore::empty();
            for c in tls::read_certs(ca)? {
                roots.add(c).map_err(|e| HttpError::Tls(format!("{}: {e}", ca.display())))?;
            }
            let config = rustls::ClientConfig::builder_with_provider(tls::provider())
                .with_safe_default_protocol_versions()
                .map_err(|e| HttpError::Tls(e.to_string()))?
                .with_root_certificates(roots)
                .with_no_client_auth();
            let name = ServerName::try_from(host.clone()).map_err(|_| bad("the host is not a valid TLS server name"))?;
            Some((tokio_rustls::TlsConnector::from(Arc::new(config)), name))
        } else {
            None
        };
        let writer = format!("grove-{}", random_hex(8)?);
        Ok(Endpoint { host, port, token, tls, writer })
    }

    /// The server's host and port, as shown in a report (never the token).
    pub fn shown(&self) -> String {
        format!("{}://{}:{}", if self.tls.is_some() { "https" } else { "http" }, self.host, self.port)
    }

    /// Opens a connection within `timeout`.
    pub async fn connect(&self, timeout: Duration) -> Result<Conn, ClientError> {
        let go = async {
            let tcp = TcpStream::connect((self.host.as_str(), self.port)).await.map_err(|e| ClientError::Connection(format!("cannot connect to {}:{}: {e}", self.host, self.port)))?;
            let _ = tcp.set_nodelay(true);
            match &self.tls {
                None => handshake(TokioIo::new(tcp)).await,
                Some((connector, name)) => {
                    let stream = connector.connect(name.clone(), tcp).await.map_err(|e| ClientError::Connection(format!("TLS: {e}")))?;
                    handshake(TokioIo::new(stream)).await
                }
            }
        };
        match tokio::time::timeout(timeout, go).await {
            Ok(r) => r.map(|sender| Conn { sender, endpoint: self.clone() }),
            Err(_) => Err(ClientError::Late(format!("no connection to {}:{}", self.host, self.port), timeout.as_secs_f64())),
        }
    }
}

async fn handshake<I>(io: I) -> Result<SendRequest<Full<Bytes>>, ClientError>
where
    I: hyper::rt::Read + hyper::rt::Write + Unpin + Send + 'static,
{
    let (sender, conn) = hyper::client::conn::http1::handshake(io).await.map_err(|e| ClientError::Connection(e.to_string()))?;
    tokio::spawn(async move {
        let _ = conn.await;
    });
    Ok(sender)
}

/// One keep-alive connection.
pub struct Conn {
    sender: SendRequest<Full<Bytes>>,
    endpoint: Endpoint,
}

impl Conn {
    /// Sends a request as a session's client does (its token and its writer name) and reads the
    /// whole answer within `timeout`. An error means the connection is no longer usable (open
    /// another).
    pub async fn request(&mut self, method: Method, path: &str, body: Bytes, timeout: Duration) -> Result<Answer, ClientError> {
        let writer = self.endpoint.writer.clone();
        let reply = self.send(method, path, &[("grove-writer", writer.as_str())], body, timeout).await?;
        Ok((reply.status, reply.json()))
    }

    /// Sends a request with these headers (and the URL's token, if it had one) and reads the
    /// whole answer within `timeout`.
    pub async fn send(&mut self, method: Method, path: &str, headers: &[(&str, &str)], body: Bytes, timeout: Duration) -> Result<Reply, ClientError> {
        let broken = |e: &dyn std::fmt::Display| ClientError::Connection(e.to_string());
        let mut req = Request::builder().method(method).uri(path).header(HOST, format!("{}:{}", self.endpoint.host, self.endpoint.port));
        if let Some(t) = &self.endpoint.token {
            req = req.header(AUTHORIZATION, format!("Bearer {t}"));
        }
        for (k, v) in headers {
            let name = HeaderName::from_bytes(k.as_bytes()).map_err(|e| broken(&e))?;
            req = req.header(name, HeaderValue::from_str(v).map_err(|e| broken(&e))?);
        }
        let req = req.body(Full::new(body)).map_err(|e| broken(&e))?;
        let go = async {
            self.sender.ready().await.map_err(|e| broken(&e))?;
            let resp = self.sender.send_request(req).await.map_err(|e| broken(&e))?;
            let (parts, body) = resp.into_parts();
            let body = body.collect().await.map_err(|e| broken(&e))?.to_bytes();
            Ok::<_, ClientError>(Reply { status: parts.status.as_u16(), headers: parts.headers, body })
        };
        match tokio::time::timeout(timeout, go).await {
            Ok(r) => r,
            Err(_) => Err(ClientError::Late("no answer".into(), timeout.as_secs_f64())),
        }
    }
}
