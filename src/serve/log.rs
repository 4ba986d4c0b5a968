//! The server's log: one line on stdout, prefixed by the time.

/// Prints one line of the server's log (stdout), prefixed by the time.
pub fn log(line: &str) {
    println!("{} {line}", chrono::DateTime::<chrono::Utc>::from(std::time::SystemTime::now()).format("%H:%M:%S"));
}
