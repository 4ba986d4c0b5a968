//! Many connections (`docs/serve.md`, "Limits and timeouts"): idle connections give way to one
//! that sends, so 600 of them do not keep a push from being served (its time beside its baseline
//! is a benchmark figure, `grove bench serve-idle`); an address whose connections are all busy
//! gets no more, and the others are served.

use std::io::{Read, Write};
use std::net::TcpStream;
use std::path::Path;
use std::time::Duration;

use crate::common::scratch;
use crate::serve_fixture::{push, read_answer, request, Server};

/// Whether the server has closed a connection the test holds (end of stream or a reset).
fn closed_by_server(s: &mut TcpStream) -> bool {
    s.set_read_timeout(Some(Duration::from_millis(20))).unwrap();
    match s.read(&mut [0u8; 1]) {
        Ok(0) => true,
        Ok(_) => false,
        Err(e) => !matches!(e.kind(), std::io::ErrorKind::WouldBlock | std::io::ErrorKind::TimedOut),
    }
}

#[test]
fn six_hundred_idle_connections_do_not_keep_a_push_from_being_served() {
    let dir = scratch("serve-crowd");
    // A read time longer than the push may wait: idle connections are not closed for being slow
    // within this test, only to make room.
    let server = Server::start(&dir, 0, &["--read-timeout", "120"]);
    let mut idle: Vec<TcpStream> = (0..600).map(|_| TcpStream::connect(&server.addr).expect("a connection")).collect();
    std::thread::sleep(Duration::from_millis(300));
    let path = Path::new("replays/study/P05-manual-7.jsonl");
    let out = push(path, &server.url, &["--timeout", "5", "--give-up", "20", "--json"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(report["ended"]["verification"]["status"], "verified", "{report}");
    assert!(std::fs::read(dir.join("P05-manual-7-1.jsonl")).unwrap() == std::fs::read(path).unwrap());
    // 600 idle connections and the push's from one address, 256 at most: the idle ones closed.
    let closed = idle.iter_mut().map(closed_by_server).filter(|c| *c).count();
    assert!(closed >= 600 - 256, "{closed} idle connections closed");
    assert_eq!(request(&server.addr, "GET", "/api/status", &[], b"").status, 200);
}

#[test]
fn an_address_whose_connections_are_all_busy_gets_no_more_and_another_address_is_served() {
    let dir = scratch("serve-per-address");
    let server = Server::start(&dir, 0, &["--max-connections-per-address", "3", "--read-timeout", "10"]);
    // Three requests whose bodies are still arriving: three busy connections from 127.0.0.1.
    let busy: Vec<TcpStream> = (0..3)
        .map(|_| {
            let mut s = TcpStream::connect(&server.addr).unwrap();
            s.write_all(b"POST /api/sessions HTTP/1.1\r\nHost: x\r\ngrove-writer: w\r\nContent-Length: 1000\r\n\r\n{\"hea").unwrap();
            s
        })
        .collect();
    std::thread::sleep(Duration::from_millis(300));
    let mut fourth = TcpStream::connect(&server.addr).unwrap();
    fourth.write_all(b"GET /api/status HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n").unwrap();
    fourth.set_read_timeout(Some(Duration::from_secs(5))).unwrap();
    assert_eq!(read_answer(&mut fourth).status, 0, "a fourth connection from the address is closed unanswered");
    // Another address (127.0.0.2, also this machine) is served.
    let runtime = tokio::runtime::Builder::new_current_thread().enable_all().build().unwrap();
    let answer = runtime.block_on(async {
        use tokio::io::{AsyncReadExt, AsyncWriteExt};
        let socket = tokio::net::TcpSocket::new_v4().unwrap();
        socket.bind("127.0.0.2:0".parse().unwrap()).unwrap();
        let mut s = socket.connect(server.addr.parse().unwrap()).await.unwrap();
        s.write_all(b"GET /api/status HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n").await.unwrap();
        let mut raw = Vec::new();
        let _ = tokio::time::timeout(Duration::from_secs(5), s.read_to_end(&mut raw)).await;
        String::from_utf8_lossy(&raw).into_owned()
    });
    assert!(answer.starts_with("HTTP/1.1 200"), "{answer}");
    drop(busy);
}
