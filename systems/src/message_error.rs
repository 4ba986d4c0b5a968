//! Errors that are one line of text for now: a newtype over the message with `Display`, `Error`
//! and a conversion back to `String` for the private helpers that still build messages.

/// Declares `pub struct $name(pub String)` as such an error, with the given doc comment.
macro_rules! message_error {
    ($(#[$doc:meta])* $name:ident) => {
        $(#[$doc])*
        #[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
        #[error("{0}")]
        pub struct $name(pub String);

        impl From<$name> for String {
            fn from(e: $name) -> String {
                e.0
            }
        }
    };
}

pub(crate) use message_error;
