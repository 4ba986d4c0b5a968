//! What the `grove serve` tests share: a server process on a free port in a scratch folder (its
//! log collected), a request through the server's own HTTP client, an answer read off a socket
//! the test writes itself (so that it controls every byte), a TCP proxy that can stop
//! forwarding, and the study's recordings.

#![allow(dead_code)]

use std::io::{BufRead, BufReader, Read, Write};
use std::net::{Shutdown, TcpListener, TcpStream};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use grove::serve::client::conn::Endpoint;
use hyper::Method;

use crate::common::root;

/// A `grove serve` process, ended when dropped.
pub struct Server {
    pub child: Child,
    /// The URL it printed (with `?token=` when it has one).
    pub url: String,
    /// `127.0.0.1:PORT`.
    pub addr: String,
    pub log: Arc<Mutex<String>>,
}

impl Server {
    /// Starts `grove serve --out DIR --port PORT ARGS…` and waits until it listens.
    pub fn start(dir: &Path, port: u16, args: &[&str]) -> Server {
        let mut child = Command::new(env!("CARGO_BIN_EXE_grove"))
            .args(["serve", "--out"])
            .arg(dir)
            .args(["--port", &port.to_string()])
            .args(args)
            .current_dir(root())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("grove serve starts");
        let log = Arc::new(Mutex::new(String::new()));
        for stream in [Box::new(child.stdout.take().unwrap()) as Box<dyn Read + Send>, Box::new(child.stderr.take().unwrap())] {
            let log = log.clone();
            std::thread::spawn(move || {
                for line in BufReader::new(stream).lines().map_while(Result::ok) {
                    let mut l = log.lock().unwrap();
                    l.push_str(&line);
                    l.push('\n');
                }
            });
        }
        let start = Instant::now();
        let url = loop {
            if let Some(u) = log.lock().unwrap().split("listening on ").nth(1).and_then(|r| r.split_whitespace().next()) {
                break u.to_string();
            }
            if let Ok(Some(status)) = child.try_wait() {
                panic!("grove serve ended ({status}): {}", log.lock().unwrap());
            }
            assert!(start.elapsed() < Duration::from_secs(30), "grove serve did not listen: {}", log.lock().unwrap());
            std::thread::sleep(Duration::from_millis(20));
        };
        let port = url.rsplit(':').next().unwrap().split('/').next().unwrap().to_string();
        Server { child, url, addr: format!("127.0.0.1:{port}"), log }
    }

    pub fn port(&self) -> u16 {
        self.addr.rsplit(':').next().unwrap().parse().unwrap()
    }

    /// The server's log so far.
    pub fn log(&self) -> String {
        self.log.lock().unwrap().clone()
    }

    /// Waits until the log has `needle` (true) or `timeout` passes (false).
    pub fn wait_log(&self, needle: &str, timeout: Duration) -> bool {
        let start = Instant::now();
        while start.elapsed() < timeout {
            if self.log().contains(needle) {
                return true;
            }
            std::thread::sleep(Duration::from_millis(20));
        }
        false
    }

    /// Sends a signal and waits for the process to end.
    pub fn signal(&mut self, sig: i32) -> std::process::ExitStatus {
        // SAFETY: a signal to the child this test started.
        unsafe {
            libc::kill(self.child.id() as i32, sig);
        }
        self.child.wait().unwrap()
    }

    /// The server's resident memory peak (VmHWM), KiB.
    pub fn peak_kib(&self) -> u64 {
        let status = std::fs::read_to_string(format!("/proc/{}/status", self.child.id())).unwrap();
        status.lines().find_map(|l| l.strip_prefix("VmHWM:")).unwrap().split_whitespace().next().unwrap().parse().unwrap()
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// An answer: status and JSON body (`Null` when not JSON) and the raw head.
pub struct Answer {
    pub status: u16,
    pub json: serde_json::Value,
    pub head: String,
    pub body: String,
}

/// One request on a new connection, read to the end, through the server's own HTTP client
/// (`grove::serve::client::conn`, as `grove serve push` and `bench` send theirs); status 0 when
/// no answer came (the connection failed or broke).
pub fn request(addr: &str, method: &str, path: &str, headers: &[(&str, &str)], body: &[u8]) -> Answer {
    let runtime = tokio::runtime::Builder::new_current_thread().enable_all().build().unwrap();
    let reply = runtime.block_on(async {
        let endpoint = Endpoint::parse(&format!("http://{addr}/"), None).expect("the server's address");
        let method = Method::from_bytes(method.as_bytes()).expect("a method");
        let timeout = Duration::from_secs(30);
        endpoint.connect(timeout).await?.send(method, path, headers, bytes::Bytes::copy_from_slice(body), timeout).await
    });
    match reply {
        Ok(r) => {
            let mut head = format!("HTTP/1.1 {}", r.status);
            for (name, value) in &r.headers {
                head.push_str(&format!("\r\n{name}: {}", String::from_utf8_lossy(value.as_bytes())));
            }
            Answer { status: r.status, json: r.json(), head, body: String::from_utf8_lossy(&r.body).into_owned() }
        }
        Err(_) => Answer { status: 0, json: serde_json::Value::Null, head: String::new(), body: String::new() },
    }
}

/// Reads a whole answer from a connection the server closes, for the tests that write a
/// request's bytes themselves (a head or body one byte at a time).
pub fn read_answer(s: &mut TcpStream) -> Answer {
    let mut raw = Vec::new();
    let _ = s.read_to_end(&mut raw);
    let text = String::from_utf8_lossy(&raw).into_owned();
    let (head, body) = text.split_once("\r\n\r\n").unwrap_or((&text, ""));
    let status = head.split_whitespace().nth(1).and_then(|c| c.parse().ok()).unwrap_or(0);
    Answer { status, json: serde_json::from_str(body.trim()).unwrap_or(serde_json::Value::Null), head: head.to_string(), body: body.to_string() }
}

/// A session opened with a header line by writer `w`; returns its id and file name.
pub fn open(addr: &str, w: &str, header: &str, token: Option<&str>) -> (String, String) {
    let body = serde_json::json!({ "header": header }).to_string();
    let bearer = token.map(|t| format!("Bearer {t}"));
    let mut h = vec![("grove-writer", w)];
    if let Some(b) = &bearer {
        h.push(("authorization", b));
    }
    let a = request(addr, "POST", "/api/sessions", &h, body.as_bytes());
    assert_eq!(a.status, 201, "{}", a.body);
    (a.json["session"].as_str().unwrap().to_string(), a.json["file"].as_str().unwrap().to_string())
}

/// Appends lines (each given without its newline) from line `from`.
pub fn append(addr: &str, w: &str, id: &str, from: u64, lines: &[String]) -> Answer {
    let body: String = lines.iter().map(|l| format!("{l}\n")).collect();
    request(addr, "POST", &format!("/api/sessions/{id}/lines?from={from}"), &[("grove-writer", w)], body.as_bytes())
}

/// The lines of a study recording (without newlines).
pub fn study_lines(name: &str) -> Vec<String> {
    std::fs::read_to_string(root().join("replays/study").join(name)).unwrap().lines().map(str::to_string).collect()
}

/// Every study recording's path, sorted.
pub fn study_files() -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(root().join("replays/study")).unwrap().map(|e| e.unwrap().path()).filter(|p| p.extension().is_some_and(|e| e == "jsonl")).collect();
    v.sort();
    v
}

/// Waits until a file has at least `n` lines; panics after `timeout`.
pub fn wait_lines(path: &Path, n: usize, timeout: Duration) {
    let start = Instant::now();
    while std::fs::read_to_string(path).map_or(0, |t| t.lines().count()) < n {
        assert!(start.elapsed() < timeout, "{} did not reach {n} lines", path.display());
        std::thread::sleep(Duration::from_millis(10));
    }
}

/// Runs `grove serve push FILE --to URL ARGS…`.
pub fn push(file: &Path, url: &str, args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_grove")).args(["serve", "push"]).arg(file).args(["--to", url]).args(args).current_dir(root()).output().unwrap()
}

/// Starts `grove serve push` without waiting.
pub fn spawn_push(file: &Path, url: &str, args: &[&str]) -> Child {
    Command::new(env!("CARGO_BIN_EXE_grove")).args(["serve", "push"]).arg(file).args(["--to", url]).args(args).current_dir(root()).stdout(Stdio::piped()).stderr(Stdio::piped()).spawn().unwrap()
}

/// A TCP proxy to `target` on its own port. While dropped, bytes go nowhere and new
/// connections are accepted but never connected (a network that is gone); on restore the
/// connections of the drop are closed and forwarding goes on.
pub struct Proxy {
    pub addr: String,
    dropped: Arc<AtomicBool>,
    generation: Arc<std::sync::atomic::AtomicU64>,
}

impl Proxy {
    pub fn start(target: &str) -> Proxy {
        let listener = TcpListener::bind("127.0.0.1:0").unwrap();
        let addr = listener.local_addr().unwrap().to_string();
        let dropped = Arc::new(AtomicBool::new(false));
        let generation = Arc::new(std::sync::atomic::AtomicU64::new(0));
        let (d, g, target) = (dropped.clone(), generation.clone(), target.to_string());
        std::thread::spawn(move || {
            for client in listener.incoming().map_while(Result::ok) {
                let (d, g, target) = (d.clone(), g.clone(), target.clone());
                std::thread::spawn(move || forward(client, &target, &d, &g));
            }
        });
        Proxy { addr, dropped, generation }
    }

    pub fn drop_network(&self) {
        self.dropped.store(true, Ordering::SeqCst);
    }

    pub fn restore(&self) {
        self.generation.fetch_add(1, Ordering::SeqCst);
        self.dropped.store(false, Ordering::SeqCst);
    }
}

/// Forwards one connection both ways until either side closes, the network drops (bytes are
/// then swallowed) or the drop ends (the connection is then closed).
fn forward(client: TcpStream, target: &str, dropped: &Arc<AtomicBool>, generation: &Arc<std::sync::atomic::AtomicU64>) {
    let born = generation.load(Ordering::SeqCst);
    let was_dropped = dropped.load(Ordering::SeqCst);
    let alive = |d: &AtomicBool, g: &std::sync::atomic::AtomicU64| {
        let now = g.load(Ordering::SeqCst);
        if was_dropped { now == born && d.load(Ordering::SeqCst) } else { now == born }
    };
    if was_dropped {
        // Accepted, never connected: hold it until the network comes back, then close it.
        while alive(dropped, generation) {
            std::thread::sleep(Duration::from_millis(20));
        }
        return;
    }
    let Ok(server) = TcpStream::connect(target) else { return };
    for (from, to) in [(client.try_clone().unwrap(), server.try_clone().unwrap()), (server.try_clone().unwrap(), client.try_clone().unwrap())] {
        let (d, g) = (dropped.clone(), generation.clone());
        std::thread::spawn(move || pipe(from, to, &d, &g, born));
    }
    while alive(dropped, generation) {
        std::thread::sleep(Duration::from_millis(20));
    }
    let _ = client.shutdown(Shutdown::Both);
    let _ = server.shutdown(Shutdown::Both);
}

fn pipe(mut from: TcpStream, mut to: TcpStream, dropped: &AtomicBool, generation: &std::sync::atomic::AtomicU64, born: u64) {
    from.set_read_timeout(Some(Duration::from_millis(50))).unwrap();
    let mut buf = [0u8; 16384];
    loop {
        if generation.load(Ordering::SeqCst) != born {
            return;
        }
        match from.read(&mut buf) {
            Ok(0) => {
                let _ = to.shutdown(Shutdown::Write);
                return;
            }
            Ok(n) => {
                if !dropped.load(Ordering::SeqCst) && to.write_all(&buf[..n]).is_err() {
                    return;
                }
            }
            Err(e) if matches!(e.kind(), std::io::ErrorKind::WouldBlock | std::io::ErrorKind::TimedOut) => {}
            Err(_) => return,
        }
    }
}
