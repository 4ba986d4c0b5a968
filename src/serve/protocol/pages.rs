//! The protocol's pages, served as they are (no network, no dependency): the participant's form
//! page (`/protocol`: each step in turn, questionnaires as forms outside the headset) and the
//! researcher's live page (`/dashboard`, polling `/api/dashboard` every second).

/// `/protocol`.
pub const PROTOCOL: &str = include_str!("protocol.html");
/// `/dashboard`.
pub const DASHBOARD: &str = include_str!("dashboard.html");
