//! Why the listener could not start: the address, the certificate, the files of `--tls auto`.

/// Why the listener could not start, one line.
#[derive(Debug, thiserror::Error)]
pub enum HttpError {
    /// The address could not be listened on.
    #[error("cannot listen on {addr}: {message}")]
    Bind {
        /// The address.
        addr: String,
        /// Why.
        message: String,
    },
    /// The certificate or key could not be made or read.
    #[error("TLS: {0}")]
    Tls(String),
    /// A file or folder of the certificate could not be written.
    #[error("{path}: {message}")]
    Io {
        /// The path.
        path: String,
        /// What went wrong, one line.
        message: String,
    },
}
