//! Why the listener could not start: the address, the certificate, the files of `--tls auto`,
//! the token kept in the folder.

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
    /// The token could not be drawn.
    #[error(transparent)]
    Random(#[from] crate::serve::ids::IdError),
    /// A file or folder of the certificate or the token could not be read or written.
    #[error("{path}: {message}")]
    Io {
        /// The path.
        path: String,
        /// What went wrong, one line.
        message: String,
    },
}
