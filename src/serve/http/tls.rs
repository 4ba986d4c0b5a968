//! TLS for the server: a certificate chain and key from PEM files (`--tls CERT,KEY`), or a
//! self-signed certificate (`--tls auto`) made once with rcgen and kept in `DIR/tls/`
//! (`cert.pem`, and `key.pem` readable by its owner only), so that a headset that accepted it
//! once keeps accepting it after a restart; a client that should trust it (`grove serve push
//! --ca DIR/tls/cert.pem`) is given `cert.pem`.

use std::path::Path;
use std::sync::Arc;

use grove_systems::files::{self, Kind};
use tokio_rustls::rustls;
use tokio_rustls::rustls::pki_types::pem::PemObject;
use tokio_rustls::rustls::pki_types::{CertificateDer, PrivateKeyDer};

use crate::serve::config::TlsChoice;
use crate::serve::http::error::HttpError;

fn tls_err(e: impl std::fmt::Display) -> HttpError {
    HttpError::Tls(e.to_string())
}

/// The rustls crypto provider grove uses (ring).
pub fn provider() -> Arc<rustls::crypto::CryptoProvider> {
    Arc::new(rustls::crypto::ring::default_provider())
}

/// Reads a PEM certificate chain.
pub fn read_certs(path: &Path) -> Result<Vec<CertificateDer<'static>>, HttpError> {
    let bytes = files::read(path, Kind::Index).map_err(tls_err)?;
    let certs: Vec<_> = CertificateDer::pem_slice_iter(&bytes).collect::<Result<_, _>>().map_err(|e| HttpError::Tls(format!("{}: not a PEM certificate chain ({e:?})", path.display())))?;
    if certs.is_empty() {
        return Err(HttpError::Tls(format!("{}: no certificate in it", path.display())));
    }
    Ok(certs)
}

fn read_key(path: &Path) -> Result<PrivateKeyDer<'static>, HttpError> {
    let bytes = files::read(path, Kind::Index).map_err(tls_err)?;
    PrivateKeyDer::from_pem_slice(&bytes).map_err(|e| HttpError::Tls(format!("{}: not a PEM private key ({e:?})", path.display())))
}

/// Makes (once) the self-signed certificate of `dir/tls/` for `localhost`, 127.0.0.1 and the
/// address shown to clients; returns the paths of the certificate and the key.
fn auto_cert(dir: &Path, shown_host: &str) -> Result<(std::path::PathBuf, std::path::PathBuf), HttpError> {
    let tls_dir = dir.join("tls");
    let (cert, key) = (tls_dir.join("cert.pem"), tls_dir.join("key.pem"));
    if cert.is_file() && key.is_file() {
        return Ok((cert, key));
    }
    std::fs::create_dir_all(&tls_dir).map_err(|e| HttpError::Io { path: tls_dir.display().to_string(), message: e.to_string() })?;
    let mut names = vec!["localhost".to_string(), "127.0.0.1".to_string()];
    let bare = shown_host.trim_start_matches('[').trim_end_matches(']').to_string();
    if !names.contains(&bare) {
        names.push(bare);
    }
    let made = rcgen::generate_simple_self_signed(names).map_err(|e| HttpError::Tls(format!("cannot make a self-signed certificate: {e}")))?;
    write_private(&key, made.signing_key.serialize_pem().as_bytes())?;
    crate::atomic_write::write_atomic(&cert, made.cert.pem().as_bytes()).map_err(|e| HttpError::Io { path: cert.display().to_string(), message: format!("{e:#}") })?;
    Ok((cert, key))
}

/// Writes a file readable by its owner only (through a temporary file and a rename).
fn write_private(path: &Path, bytes: &[u8]) -> Result<(), HttpError> {
    crate::atomic_write::write_private(path, bytes).map_err(|e| HttpError::Io { path: path.display().to_string(), message: e.source.to_string() })
}

/// The server's TLS configuration for a choice, if any.
pub fn acceptor(choice: &TlsChoice, dir: &Path, shown_host: &str) -> Result<Option<Arc<rustls::ServerConfig>>, HttpError> {
    let (cert, key) = match choice {
        TlsChoice::Off => return Ok(None),
        TlsChoice::Auto => auto_cert(dir, shown_host)?,
        TlsChoice::Files { cert, key } => (cert.clone(), key.clone()),
    };
    let certs = read_certs(&cert)?;
    let key = read_key(&key)?;
    let mut config = rustls::ServerConfig::builder_with_provider(provider())
        .with_safe_default_protocol_versions()
        .map_err(tls_err)?
        .with_no_client_auth()
        .with_single_cert(certs, key)
        .map_err(|e| HttpError::Tls(format!("the certificate and key do not go together: {e}")))?;
    config.alpn_protocols = vec![b"http/1.1".to_vec()];
    Ok(Some(Arc::new(config)))
}
