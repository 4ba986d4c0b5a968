//! `grove bench serve-idle`: how long a push takes while 600 idle connections are open
//! (`docs/serve.md`, "Limits and timeouts": idle connections give way to one that sends). Two
//! `grove serve` processes of its own on loopback are pushed the same study recordings at full
//! speed, one after the other; one of them holds 600 connections that never send a request,
//! opened before its first push from three addresses (127.0.0.2 to 127.0.0.4, 200 each: under the
//! per-address limit, over the total of 512). The figures are the median push of each and their
//! ratio, whose goal is at most 2.

use std::path::Path;
use std::time::{Duration, Instant};

use serde_json::{json, Value};

use super::{median, BenchError};
use crate::serve::client::bench::start_server;
use crate::serve::client::conn::Endpoint;
use crate::serve::client::push::{push, PushOptions, Rate};

/// Idle connections held open.
const IDLE: usize = 600;
/// The addresses they come from (127.0.0.2 onwards).
const ADDRESSES: u8 = 3;
/// The recordings pushed to each server.
const RECORDINGS: [&str; 6] = ["P01-manual-7.jsonl", "P02-manual-7.jsonl", "P03-manual-7.jsonl", "P04-manual-7.jsonl", "P05-manual-7.jsonl", "P06-manual-7.jsonl"];

fn failed(what: impl std::fmt::Display) -> BenchError {
    BenchError::Serve(what.to_string())
}

/// Runs the benchmark with `grove` (this program) as the servers.
pub fn bench_serve_idle(grove: &Path) -> Result<Value, BenchError> {
    let scratch = std::env::temp_dir().join(format!("grove-bench-serve-idle-{}", std::process::id()));
    std::fs::create_dir_all(&scratch).map_err(|source| BenchError::Folder { path: scratch.clone(), source })?;
    // As `grove bench study` does: the recordings of the working directory's replays/study.
    let study = Path::new("replays/study");
    let mut baseline = start_server(grove, &scratch.join("baseline"), true).map_err(failed)?;
    let mut crowded = start_server(grove, &scratch.join("crowded"), true).map_err(failed)?;
    let runtime = tokio::runtime::Builder::new_multi_thread().enable_all().build().map_err(failed)?;
    let result = runtime.block_on(async {
        let addr: std::net::SocketAddr = crowded.url.trim_start_matches("http://").trim_end_matches('/').parse().map_err(failed)?;
        let mut idle = Vec::new();
        for i in 0..IDLE {
            let socket = tokio::net::TcpSocket::new_v4().map_err(failed)?;
            socket.bind((std::net::Ipv4Addr::new(127, 0, 0, 2 + (i % ADDRESSES as usize) as u8), 0).into()).map_err(failed)?;
            idle.push(socket.connect(addr).await.map_err(failed)?);
        }
        tokio::time::sleep(Duration::from_millis(300)).await;
        let options = PushOptions { rate: Rate::Max, timeout: Duration::from_secs(10), give_up: Duration::from_secs(60), max_batch_bytes: 256 * 1024 };
        let (mut alone, mut with_idle) = (Vec::new(), Vec::new());
        let mut lines = 0;
        for name in RECORDINGS {
            let file = study.join(name);
            for (server, times) in [(&baseline, &mut alone), (&crowded, &mut with_idle)] {
                let endpoint = Endpoint::parse(&server.url, None).map_err(failed)?;
                let start = Instant::now();
                let report = push(&file, &endpoint, &options, &|_| {}).await.map_err(failed)?;
                times.push(start.elapsed().as_secs_f64());
                lines = report.lines.max(lines);
            }
        }
        let open = idle.iter().filter(|s| s.try_read(&mut [0u8; 1]).is_err_and(|e| e.kind() == std::io::ErrorKind::WouldBlock)).count();
        Ok::<_, BenchError>((alone, with_idle, lines, IDLE - open))
    });
    let _ = baseline.child.kill();
    let _ = crowded.child.kill();
    let _ = baseline.child.wait();
    let _ = crowded.child.wait();
    let _ = std::fs::remove_dir_all(&scratch);
    let (mut alone, mut with_idle, lines, closed) = result?;
    let (a, b) = (median(&mut alone), median(&mut with_idle));
    let round = |x: f64| (x * 1e4).round() / 1e4;
    Ok(json!({
        "idle_connections": IDLE,
        "idle_addresses": ADDRESSES,
        "idle_closed_to_make_room": closed,
        "pushes": RECORDINGS.len(),
        "recording_lines_max": lines,
        "push_s_median_alone": round(a),
        "push_s_median_with_idle": round(b),
        "ratio": round(b / a),
        "goal_ratio": 2.0,
    }))
}
