//! The server's routers answer alike (`docs/serve.md`, "Routes"): on the sessions' routes, the
//! protocol's and the server's own, a path no route has is refused with 404 `no route PATH`, and
//! a path served under other methods only with 405, the methods it takes in the reason and in
//! `Allow`; the files refuse a method other than GET and HEAD the same way.

use crate::common::scratch;
use crate::serve_fixture::{request, Server};

#[test]
fn a_wrong_method_and_an_unknown_path_are_answered_alike_on_every_router() {
    let dir = scratch("serve-routes");
    let server = Server::start(&dir, 0, &["--protocol", "assets/protocols/tree-planting.ron"]);
    let id = "0123456789abcdef0123456789abcdef";
    for path in [format!("/api/sessions/{id}/lines/more"), "/api/sessions/x/y/z".into(), "/api/protocol/participants/P01/skip".into(), "/api/protocol/nothing".into(), "/api/nothing".into()] {
        let r = request(&server.addr, "GET", &path, &[], b"");
        assert_eq!(r.status, 404, "{path}: {}", r.body);
        assert_eq!(r.json, serde_json::json!({ "error": format!("no route {path}") }), "{path}");
        assert!(!r.head.contains("\r\nallow:"), "{path}: {}", r.head);
    }
    for (method, path, allow) in [
        ("DELETE", "/api/sessions".to_string(), "GET, POST"),
        ("PUT", format!("/api/sessions/{id}/end"), "POST"),
        ("POST", format!("/api/sessions/{id}/scene"), "GET"),
        ("DELETE", "/api/protocol/participants".into(), "POST"),
        ("GET", "/api/protocol/participants/P01/next".into(), "POST"),
        ("POST", "/dashboard".into(), "GET"),
        ("POST", "/api/status".into(), "GET"),
        ("DELETE", "/scenes/study.ron".into(), "GET, HEAD"),
    ] {
        let r = request(&server.addr, method, &path, &[], b"");
        assert_eq!(r.status, 405, "{method} {path}: {}", r.body);
        assert_eq!(r.json, serde_json::json!({ "error": format!("{method} is not served at {path}; it takes {allow}") }), "{method} {path}");
        assert!(r.head.contains(&format!("\r\nallow: {allow}")), "{method} {path}: {}", r.head);
    }
    assert!(!server.log().contains("refused"), "neither is logged: {}", server.log());
    assert_eq!(request(&server.addr, "GET", "/api/status", &[], b"").status, 200, "still serving");
}
