//! Files served as they are: the page (`web/dist/`, at `/`), the client library
//! (`web/client/`, at `/client/`), the simulation's module (its loader `web/sim/`, at `/sim/`,
//! and `target/wasm/grove_sim.wasm`, at the same path, where the loader looks), the scenes,
//! tasks, shipped tree models and controller models (`assets/…`, at `/scenes/`, `/tasks/`,
//! `/models/shipped/`, `/controllers/`) and every model bank (`/models/banks/NAME/`).
//!
//! A URL path never leads out of its folder: it is decoded once, and each of its parts must be a
//! plain name (not empty, not `.` or `..`, no `/`, `\`, NUL or leading dot, so no hidden file);
//! the file found must then lie inside the folder by canonical path (no symbolic link out), be
//! a regular file within the size limit, and is read through `grove_systems::files`. Whatever is
//! refused gets 404 with the reason; a method other than GET and HEAD gets 405, as from the routers.

use std::path::{Path, PathBuf};

use bytes::Bytes;
use futures_util::stream;
use grove_systems::files::{self, Kind};
use http_body_util::{BodyExt, StreamBody};
use hyper::body::Frame;
use hyper::{Method, Response, StatusCode};
use tokio::io::AsyncReadExt;

use crate::serve::http::refusal::Refusal;
use crate::serve::http::respond::{full, Body};
use crate::serve::http::router::wrong_method;

/// A URL prefix and the folder it maps to.
#[derive(Clone, Debug)]
struct Root {
    prefix: String,
    dir: PathBuf,
    /// The one file of the folder served, where only one is.
    only: Option<&'static str>,
}

/// The folders served, by URL prefix.
#[derive(Clone, Debug)]
pub struct StaticRoots {
    roots: Vec<Root>,
}

impl StaticRoots {
    /// The roots of a web folder, an assets folder and the given model banks (the assets'
    /// own banks, `assets/banks/*`, come first).
    pub fn new(web: &Path, assets: &Path, wasm: &Path, banks: &[PathBuf]) -> StaticRoots {
        let mut roots = vec![
            // Where `web/sim/grove-sim.mjs` looks for the module by default, relative to itself.
            Root { prefix: "/target/wasm/".into(), dir: wasm.to_path_buf(), only: Some("grove_sim.wasm") },
            Root { prefix: "/client/".into(), dir: web.join("client"), only: None },
            Root { prefix: "/sim/".into(), dir: web.join("sim"), only: None },
            Root { prefix: "/scenes/".into(), dir: assets.join("scenes"), only: None },
            Root { prefix: "/tasks/".into(), dir: assets.join("tasks"), only: None },
            Root { prefix: "/models/shipped/".into(), dir: assets.join("trees"), only: None },
            Root { prefix: "/controllers/".into(), dir: assets.join("controllers"), only: None },
        ];
        let mut bank_dirs: Vec<PathBuf> = std::fs::read_dir(assets.join("banks")).into_iter().flatten().flatten().map(|e| e.path()).filter(|p| p.is_dir()).collect();
        bank_dirs.sort();
        bank_dirs.extend(banks.iter().cloned());
        let mut names: Vec<String> = Vec::new();
        for dir in bank_dirs {
            let base: String = dir.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_else(|| "bank".into());
            let base: String = base.chars().map(|c| if c.is_ascii_alphanumeric() || c == '-' || c == '_' { c } else { '_' }).collect();
            let mut name = base.clone();
            let mut k = 2;
            while names.contains(&name) {
                name = format!("{base}-{k}");
                k += 1;
            }
            names.push(name.clone());
            roots.push(Root { prefix: format!("/models/banks/{name}/"), dir, only: None });
        }
        // The page last: it has the shortest prefix.
        roots.push(Root { prefix: "/".into(), dir: web.join("dist"), only: None });
        StaticRoots { roots }
    }

    /// Whether a built page (`web/dist/index.html`) exists.
    pub fn has_page(&self) -> bool {
        self.roots.last().is_some_and(|r| r.dir.join("index.html").is_file())
    }

    /// What is served: per root, the URLs of its files (one level of folders deep), as JSON.
    pub fn index(&self) -> serde_json::Value {
        let mut out = serde_json::Map::new();
        for r in &self.roots {
            if r.prefix == "/" || !r.dir.is_dir() {
                continue;
            }
            let mut urls = Vec::new();
            match r.only {
                Some(name) if r.dir.join(name).is_file() => urls.push(format!("{}{name}", r.prefix)),
                Some(_) => {}
                None => list(&r.dir, &r.dir, &r.prefix, 2, &mut urls),
            }
            urls.sort();
            out.insert(r.prefix.trim_matches('/').to_string(), serde_json::Value::from(urls));
        }
        serde_json::Value::Object(out)
    }

    /// The file a URL path names, checked (see the module's documentation).
    pub fn resolve(&self, url_path: &str) -> Result<PathBuf, Refusal> {
        let decoded = percent_encoding::percent_decode_str(url_path).decode_utf8().map_err(|_| Refusal::not_found("the path is not UTF-8 once decoded"))?;
        let root = self.roots.iter().find(|r| decoded.starts_with(&r.prefix) || (decoded == r.prefix.trim_end_matches('/') && r.prefix != "/")).ok_or_else(|| Refusal::not_found("nothing is served there"))?;
        let rest = decoded.strip_prefix(&root.prefix).unwrap_or("");
        if root.only.is_some_and(|name| rest != name) {
            return Err(Refusal::not_found("only the module is served there"));
        }
        let mut path = root.dir.clone();
        let parts: Vec<&str> = if rest.is_empty() { Vec::new() } else { rest.split('/').collect() };
        for (i, part) in parts.iter().enumerate() {
            let last = i + 1 == parts.len();
            if part.is_empty() && last {
                break;
            }
            if part.is_empty() || *part == "." || *part == ".." || part.starts_with('.') || part.contains(['\\', '\0', ':']) {
                return Err(Refusal::not_found(format!("the path part {part:?} is not a plain name; only files inside the served folders are sent")));
            }
            path.push(part);
        }
        if path.is_dir() {
            path.push("index.html");
        }
        let real = files::within(&path, &root.dir).map_err(|e| not_served(&decoded, &e))?;
        files::check(&real, Kind::Served).map_err(|e| not_served(&decoded, &e))?;
        Ok(real)
    }

    /// Answers a request for a file: GET and HEAD are served, any other method is refused as
    /// the routers refuse it (405).
    pub async fn answer(&self, method: &Method, url_path: &str) -> Result<Response<Body>, Refusal> {
        match *method {
            Method::GET => self.serve(url_path, false).await,
            Method::HEAD => self.serve(url_path, true).await,
            _ => Err(wrong_method(method, url_path, &[Method::GET, Method::HEAD])),
        }
    }

    /// Serves a URL path: the file, streamed, with its content type (no body for HEAD).
    pub async fn serve(&self, url_path: &str, head: bool) -> Result<Response<Body>, Refusal> {
        let path = self.resolve(url_path)?;
        let opened = tokio::task::spawn_blocking({
            let path = path.clone();
            move || files::open(&path, Kind::Served)
        })
        .await
        .map_err(|e| Refusal::internal(e.to_string()))?;
        let (file, len) = opened.map_err(|e| not_served(url_path, &e))?;
        let body = if head {
            full(Bytes::new())
        } else {
            let file = tokio::fs::File::from_std(file);
            let chunks = stream::unfold((Some(file), len), |(file, left)| async move {
                let mut f = file?;
                if left == 0 {
                    return None;
                }
                let mut buf = vec![0u8; (64 * 1024).min(left as usize)];
                match f.read(&mut buf).await {
                    Ok(0) => None,
                    Ok(n) => {
                        buf.truncate(n);
                        Some((Ok(Frame::data(Bytes::from(buf))), (Some(f), left - n as u64)))
                    }
                    Err(e) => Some((Err(e), (None, 0))),
                }
            });
            StreamBody::new(chunks).boxed()
        };
        let mut r = Response::new(body);
        *r.status_mut() = StatusCode::OK;
        let h = r.headers_mut();
        h.insert(hyper::header::CONTENT_TYPE, hyper::header::HeaderValue::from_static(content_type(&path)));
        h.insert(hyper::header::CONTENT_LENGTH, hyper::header::HeaderValue::from(len));
        h.insert(hyper::header::CACHE_CONTROL, hyper::header::HeaderValue::from_static("no-cache"));
        h.insert("x-content-type-options", hyper::header::HeaderValue::from_static("nosniff"));
        Ok(r)
    }
}

/// 404 for a URL whose file is not served, naming the URL and why, never a path of the machine.
fn not_served(url_path: &str, e: &files::FileError) -> Refusal {
    Refusal::not_found(format!("{url_path}: {}", e.public_reason()))
}

/// What a file name's characters become in a URL: all but letters, digits and `-._~` encoded.
const URL_PART: &percent_encoding::AsciiSet = &percent_encoding::NON_ALPHANUMERIC.remove(b'-').remove(b'.').remove(b'_').remove(b'~');

/// The URLs of the files under `dir`, down to `depth` levels, hidden files left out, as they are
/// served: nothing that lies outside `root` (through a symbolic link) is listed.
fn list(root: &Path, dir: &Path, prefix: &str, depth: u32, out: &mut Vec<String>) {
    for e in std::fs::read_dir(dir).into_iter().flatten().flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        if name.starts_with('.') {
            continue;
        }
        let p = e.path();
        if files::within(&p, root).is_err() {
            continue;
        }
        if p.is_dir() && depth > 1 {
            list(root, &p, &format!("{prefix}{}/", percent_encoding::utf8_percent_encode(&name, URL_PART)), depth - 1, out);
        } else if p.is_file() {
            out.push(format!("{prefix}{}", percent_encoding::utf8_percent_encode(&name, URL_PART)));
        }
    }
}

/// The content type of a file by its extension.
pub fn content_type(path: &Path) -> &'static str {
    match path.extension().and_then(|e| e.to_str()).unwrap_or("") {
        "html" | "htm" => "text/html; charset=utf-8",
        "js" | "mjs" => "text/javascript; charset=utf-8",
        "css" => "text/css; charset=utf-8",
        "json" | "map" => "application/json",
        "wasm" => "application/wasm",
        "gltf" => "model/gltf+json",
        "glb" => "model/gltf-binary",
        "png" => "image/png",
        "jpg" | "jpeg" => "image/jpeg",
        "webp" => "image/webp",
        "svg" => "image/svg+xml",
        "ron" | "txt" | "md" => "text/plain; charset=utf-8",
        "jsonl" => "application/jsonl",
        _ => "application/octet-stream",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paths_stay_inside_their_folders() {
        let d = tempfile::tempdir().unwrap();
        let web = d.path().join("web");
        let assets = d.path().join("assets");
        std::fs::create_dir_all(web.join("dist/js")).unwrap();
        std::fs::create_dir_all(assets.join("scenes")).unwrap();
        std::fs::write(web.join("dist/index.html"), "page").unwrap();
        std::fs::write(web.join("dist/js/a.js"), "js").unwrap();
        std::fs::write(web.join("dist/.env"), "secret").unwrap();
        std::fs::write(assets.join("scenes/study.ron"), "()").unwrap();
        std::fs::write(d.path().join("outside.txt"), "no").unwrap();
        #[cfg(unix)]
        std::os::unix::fs::symlink(d.path().join("outside.txt"), assets.join("scenes/link.ron")).unwrap();
        std::fs::create_dir_all(d.path().join("wasm/release")).unwrap();
        std::fs::write(d.path().join("wasm/grove_sim.wasm"), "\0asm").unwrap();
        std::fs::write(d.path().join("wasm/release/other.wasm"), "no").unwrap();
        let roots = StaticRoots::new(&web, &assets, &d.path().join("wasm"), &[]);
        let ok = |p: &str| roots.resolve(p).map(|f| std::fs::read_to_string(f).unwrap());
        assert_eq!(ok("/").unwrap(), "page");
        assert_eq!(ok("/js/a.js").unwrap(), "js");
        assert_eq!(ok("/scenes/study.ron").unwrap(), "()");
        assert_eq!(ok("/scenes/%73tudy.ron").unwrap(), "()", "decoded once");
        assert_eq!(ok("/target/wasm/grove_sim.wasm").unwrap(), "\0asm");
        assert_eq!(roots.index()["target/wasm"], serde_json::json!(["/target/wasm/grove_sim.wasm"]));
        // Nothing behind a symbolic link out of a folder is listed, and no refusal names a path
        // of the machine.
        #[cfg(unix)]
        {
            std::fs::create_dir_all(d.path().join("elsewhere")).unwrap();
            std::fs::write(d.path().join("elsewhere/secret-name.ron"), "()").unwrap();
            std::os::unix::fs::symlink(d.path().join("elsewhere"), assets.join("scenes/linked")).unwrap();
            let listed = roots.index().to_string();
            assert!(!listed.contains("secret-name") && !listed.contains("link.ron"), "{listed}");
            assert!(listed.contains("/scenes/study.ron"), "{listed}");
            for url in ["/scenes/linked/secret-name.ron", "/scenes/link.ron"] {
                let refused = roots.resolve(url).unwrap_err();
                assert!(refused.reason.starts_with(url) && !refused.reason.contains(&*d.path().to_string_lossy()), "{}", refused.reason);
            }
        }
        for bad in ["/../outside.txt", "/scenes/../../outside.txt", "/scenes/%2e%2e/%2e%2e/outside.txt", "/scenes/..%2f..%2foutside.txt", "/.env", "/scenes/link.ron", "/scenes//study.ron", "/scenes/%00", "/scenes/a%5c..%5c..%5coutside.txt", "/nothing.txt", "/target/wasm/release/other.wasm", "/target/wasm/"] {
            let r = roots.resolve(bad);
            assert!(r.as_ref().is_err_and(|e| e.status == 404), "{bad}: {r:?}");
        }
    }
}
