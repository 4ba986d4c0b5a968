//! The one router behaviour, for every route table of the server (the sessions', the
//! protocol's, the server's own) and for the files: a path that no route has is refused with
//! 404 `no route PATH`; a path that routes have, under other methods only, with 405 `METHOD is
//! not served at PATH; it takes GET, POST` and the header `Allow: GET, POST` (RFC 9110). Both
//! are JSON refusals like every other (`{"error": …}`), and neither is logged.

use hyper::Method;

use crate::serve::http::refusal::Refusal;

/// One route: a method and a path pattern, `/api/sessions/{id}/lines`, whose `{…}` parts match
/// any one path segment; `to` says where it goes.
#[derive(Clone, Debug)]
pub struct Route<T> {
    /// The method.
    pub method: Method,
    /// The path pattern.
    pub path: &'static str,
    /// Where it goes.
    pub to: T,
}

/// The path's segments that a pattern's `{…}` parts matched, if the pattern matches it.
fn matches<'p>(pattern: &str, path: &'p str) -> Option<Vec<&'p str>> {
    let (pat, segs): (Vec<&str>, Vec<&str>) = (pattern.split('/').collect(), path.split('/').collect());
    if pat.len() != segs.len() {
        return None;
    }
    let mut captured = Vec::new();
    for (p, s) in pat.iter().zip(&segs) {
        if p.starts_with('{') && p.ends_with('}') {
            captured.push(*s);
        } else if p != s {
            return None;
        }
    }
    Some(captured)
}

/// The route a request takes and the path segments its pattern captured, or the refusal: 404
/// for a path no route has, 405 for a path that routes have under other methods.
pub fn find<'p, T: Copy>(routes: &[Route<T>], method: &Method, path: &'p str) -> Result<(T, Vec<&'p str>), Refusal> {
    let mut allowed: Vec<&Method> = Vec::new();
    for r in routes {
        if let Some(captured) = matches(r.path, path) {
            if r.method == *method {
                return Ok((r.to, captured));
            }
            if !allowed.contains(&&r.method) {
                allowed.push(&r.method);
            }
        }
    }
    if allowed.is_empty() {
        return Err(Refusal::not_found(format!("no route {path}")));
    }
    Err(wrong_method(method, path, &allowed.into_iter().cloned().collect::<Vec<_>>()))
}

/// 405 for `method` at `path`, which takes `allow`.
pub fn wrong_method(method: &Method, path: &str, allow: &[Method]) -> Refusal {
    let allow = allow.iter().map(Method::as_str).collect::<Vec<_>>().join(", ");
    let mut r = Refusal::method(format!("{method} is not served at {path}; it takes {allow}"));
    r.allow = Some(allow);
    r
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Clone, Copy, Debug, PartialEq)]
    enum To {
        List,
        Open,
        Lines,
    }

    fn table() -> Vec<Route<To>> {
        vec![
            Route { method: Method::GET, path: "/api/sessions", to: To::List },
            Route { method: Method::POST, path: "/api/sessions", to: To::Open },
            Route { method: Method::POST, path: "/api/sessions/{id}/lines", to: To::Lines },
        ]
    }

    #[test]
    fn a_route_captures_its_segments_and_a_miss_is_404_or_405_with_the_methods_taken() {
        assert_eq!(find(&table(), &Method::POST, "/api/sessions/abc/lines"), Ok((To::Lines, vec!["abc"])));
        assert_eq!(find(&table(), &Method::GET, "/api/sessions"), Ok((To::List, vec![])));
        let unknown = find(&table(), &Method::GET, "/api/sessions/abc/nothing").unwrap_err();
        assert_eq!((unknown.status, unknown.reason.as_str(), unknown.allow), (404, "no route /api/sessions/abc/nothing", None));
        let wrong = find(&table(), &Method::DELETE, "/api/sessions").unwrap_err();
        assert_eq!((wrong.status, wrong.reason.as_str()), (405, "DELETE is not served at /api/sessions; it takes GET, POST"));
        assert_eq!(wrong.allow.as_deref(), Some("GET, POST"));
        assert_eq!(find(&table(), &Method::GET, "/api/sessions/abc/lines").unwrap_err().allow.as_deref(), Some("POST"));
    }
}
