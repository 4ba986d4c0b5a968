//! The page at `/` when the web folder has no built page: the sessions and what is served.

use hyper::Response;

use crate::serve::http::respond::{html, Body};
use crate::serve::sessions::registry::Entry;

/// The server's own page: its sessions (file, state, lines, verification) and the files it
/// serves (`index`: per root, the URLs of its files).
pub fn page(entries: &[Entry], index: &serde_json::Value) -> Response<Body> {
    let page = maud::html! {
        (maud::DOCTYPE)
        html lang="en" {
            head { meta charset="utf-8"; title { "grove serve" } }
            body style="font-family: sans-serif; max-width: 60em; margin: 2em auto" {
                h1 { "grove serve " (env!("CARGO_PKG_VERSION")) }
                p { "A session server: clients stream recordings here (" code { "docs/serve.md" } "). No page is built in the web folder yet." }
                h2 { "Sessions" }
                @if entries.is_empty() { p { "None yet." } }
                @else {
                    table {
                        tr { th { "file" } th { "state" } th { "lines" } th { "verification" } }
                        @for e in entries {
                            tr { td { (e.file) } td { (e.state) } td { (e.lines) } td { (e.verification.as_ref().map(|v| v.summary()).unwrap_or_default()) } }
                        }
                    }
                }
                h2 { "Served files" }
                @for (name, files) in index.as_object().into_iter().flatten() {
                    h3 { (name) }
                    ul { @for f in files.as_array().into_iter().flatten() { @if let Some(u) = f.as_str() { li { a href=(u) { (u) } } } } }
                }
            }
        }
    };
    html(page.into_string())
}
