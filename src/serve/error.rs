//! Why the server could not start or stop cleanly: one line, from whichever room failed. It is
//! part of the library's one error type (`grove::Error::Serve`).

use crate::serve::client::conn::ClientError;
use crate::serve::http::error::HttpError;
use crate::serve::ids::IdError;
use crate::serve::protocol::error::ParticipantError;
use crate::serve::sessions::error::SessionError;

/// Why the server could not start or go on: one line.
#[derive(Debug, thiserror::Error)]
pub enum ServeError {
    /// The listener: the address, the certificate.
    #[error(transparent)]
    Http(#[from] HttpError),
    /// The sessions' folder: `sessions.json`, the model banks.
    #[error(transparent)]
    Sessions(#[from] SessionError),
    /// The protocol's folder: its copy of the protocol, the participants' files.
    #[error("{path}: {source}")]
    Protocol {
        /// The folder.
        path: String,
        /// What went wrong.
        source: ParticipantError,
    },
    /// The token could not be made.
    #[error(transparent)]
    Random(#[from] IdError),
    /// A client (`push`, `bench`): the server, the URL or the network.
    #[error(transparent)]
    Client(#[from] ClientError),
    /// The server's runtime could not be made.
    #[error("tokio runtime: {0}")]
    Runtime(String),
}
