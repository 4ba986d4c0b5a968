//! The protocol's pages: the participant's form page (`/protocol`: each step in turn,
//! questionnaires as forms outside the headset) and the researcher's live page (`/dashboard`,
//! polling `/api/dashboard` every second). Their markup (`web/protocol/index.html`,
//! `web/dashboard/index.html`) is built into the binary; each loads its ES module, bundled by
//! `web/page/build.mjs` into `web/dist/` (`/protocol.js`, `/dashboard.js`) and served from there
//! as the headset page is.

/// `/protocol`.
pub const PROTOCOL: &str = include_str!("../../../web/protocol/index.html");
/// `/dashboard`.
pub const DASHBOARD: &str = include_str!("../../../web/dashboard/index.html");
