//! A small HTTP/1.1 client for a session server (`grove serve push`, `grove serve bench`): one
//! keep-alive connection, plain or TLS (trusting the certificate given, as `--tls auto` makes
//! one), every request bounded in time, the token sent as `Authorization: Bearer`.

use std::path::Path;
use std::sync::Arc;
use std::time::Duration;

use bytes::Bytes;
use http_body_util::{BodyExt, Full};
use hyper::client::conn::http1::SendRequest;
use hyper::{Method, Request, Uri};
use hyper_util::rt::TokioIo;
use tokio::net::TcpStream;
use tokio_rustls::rustls;
use tokio_rustls::rustls::pki_types::ServerName;

use crate::serve::ServeError;

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

impl Endpoint {
    /// Reads a URL; an `https` URL needs `ca`, the certificate (PEM) to trust.
    pub fn parse(url: &str, ca: Option<&Path>) -> Result<Endpoint, ServeError> {
        let bad = |why: &str| ServeError::Client(format!("--to {url:?}: {why}"));
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
            for c in crate::serve::http::tls::read_certs(ca)? {
                roots.add(c).map_err(|e| ServeError::Tls(format!("{}: {e}", ca.display())))?;
            }
            let config = rustls::ClientConfig::builder_with_provider(crate::serve::http::tls::provider())
                .with_safe_default_protocol_versions()
                .map_err(|e| ServeError::Tls(e.to_string()))?
                .with_root_certificates(roots)
                .with_no_client_auth();
            let name = ServerName::try_from(host.clone()).map_err(|_| bad("the host is not a valid TLS server name"))?;
            Some((tokio_rustls::TlsConnector::from(Arc::new(config)), name))
        } else {
            None
        };
        let writer = format!("grove-{}", crate::serve::ids::random_hex(8)?);
        Ok(Endpoint { host, port, token, tls, writer })
    }

    /// Opens a connection within `timeout`.
    pub async fn connect(&self, timeout: Duration) -> Result<Conn, String> {
        let go = async {
            let tcp = TcpStream::connect((self.host.as_str(), self.port)).await.map_err(|e| format!("cannot connect to {}:{}: {e}", self.host, self.port))?;
            let _ = tcp.set_nodelay(true);
            match &self.tls {
                None => handshake(TokioIo::new(tcp)).await,
                Some((connector, name)) => {
                    let stream = connector.connect(name.clone(), tcp).await.map_err(|e| format!("TLS: {e}"))?;
                    handshake(TokioIo::new(stream)).await
                }
            }
        };
        match tokio::time::timeout(timeout, go).await {
            Ok(r) => r.map(|sender| Conn { sender, endpoint: self.clone() }),
            Err(_) => Err(format!("no connection to {}:{} within {:.1} s", self.host, self.port, timeout.as_secs_f64())),
        }
    }
}

async fn handshake<I>(io: I) -> Result<SendRequest<Full<Bytes>>, String>
where
    I: hyper::rt::Read + hyper::rt::Write + Unpin + Send + 'static,
{
    let (sender, conn) = hyper::client::conn::http1::handshake(io).await.map_err(|e| e.to_string())?;
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
    /// Sends a request and reads the whole answer within `timeout`. An error means the
    /// connection is no longer usable (open another).
    pub async fn request(&mut self, method: Method, path: &str, body: Bytes, timeout: Duration) -> Result<Answer, String> {
        let mut req = Request::builder().method(method).uri(path).header(hyper::header::HOST, format!("{}:{}", self.endpoint.host, self.endpoint.port)).header("grove-writer", &self.endpoint.writer);
        if let Some(t) = &self.endpoint.token {
            req = req.header(hyper::header::AUTHORIZATION, format!("Bearer {t}"));
        }
        let req = req.body(Full::new(body)).map_err(|e| e.to_string())?;
        let go = async {
            self.sender.ready().await.map_err(|e| e.to_string())?;
            let resp = self.sender.send_request(req).await.map_err(|e| e.to_string())?;
            let status = resp.status().as_u16();
            let bytes = resp.into_body().collect().await.map_err(|e| e.to_string())?.to_bytes();
            Ok::<_, String>((status, serde_json::from_slice(&bytes).unwrap_or(serde_json::Value::Null)))
        };
        match tokio::time::timeout(timeout, go).await {
            Ok(r) => r,
            Err(_) => Err(format!("no answer within {:.1} s", timeout.as_secs_f64())),
        }
    }
}
