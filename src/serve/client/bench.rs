//! `grove serve bench`: many sessions streaming at once to a server, as headsets would: every
//! session sends each tick's lines (a controller and a head pose at 60 Hz, a trigger press and
//! release every two seconds, a checkpoint every second) in its own request as soon as the tick
//! is made, so every button event is sent and acknowledged on its own tick. The server is this
//! grove started as a separate process on loopback (`grove serve --port 0`), so that its CPU
//! time and memory are its own, sampled once a second from `/proc`; or, with `--to URL`, a
//! server already running, on this machine or another (its CPU and memory are then not read).
//!
//! Figures: the acknowledgement time of every request (p50, p99, max), the server's CPU share
//! and resident memory per minute, each session's verification at its end, and how long after a
//! checkpoint's acknowledgement the server's live verification had verified it (read from
//! `GET /api/sessions` four times a second, as a dashboard would).

use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::Arc;
use std::time::{Duration, Instant};

use bytes::Bytes;
use glam::{Quat, Vec3};
use grove_systems::components::Pose;
use grove_systems::input::{Button, InputEvent};
use grove_systems::replay::{encode_line, Header, Line, Recorder, CHECKPOINT_EVERY};
use hyper::Method;
use serde_json::json;

use crate::serve::client::bench_live::{quantile, round, watch_live, Checkpoints};
use crate::serve::client::conn::{ClientError, Endpoint};
use crate::serve::sessions::states::VerifyStatus;

/// Options of the benchmark.
#[derive(Clone)]
pub struct BenchOptions {
    /// Sessions at once.
    pub sessions: usize,
    /// Seconds each session streams (simulated and wall-clock: 60 ticks a second).
    pub seconds: f64,
    /// The grove program that runs the server.
    pub grove: PathBuf,
    /// A server already running to stream to, in place of one of its own.
    pub to: Option<Endpoint>,
    /// Whether its own server verifies every session as it streams (`--live on`).
    pub live: bool,
}

/// One session's recording made ahead: each tick's lines as one request body, and the lines of
/// the header's successors (the same for every session: the checksum chain starts after the
/// header, and the participant changes nothing in the world).
fn recording(ticks: u64) -> Result<(Header, Vec<Bytes>), ClientError> {
    let scene = grove_systems::scene::Scene::builtin("study").ok_or_else(|| ClientError::Local("no built-in study scene".into()))?;
    let mut header = Header::new("study", 1, scene.dt);
    header.participant = Some("B01".into());
    let mut sim = grove_systems::replay::sim_for_header(&header, None, &[]).map_err(|e| ClientError::Local(e.to_string()))?;
    let mut out = Vec::new();
    let mut rec = Recorder::new(&mut out, &header).map_err(|e| ClientError::Local(e.to_string()))?;
    let fail = |e: std::io::Error| ClientError::Local(e.to_string());
    let mut batches = Vec::with_capacity(ticks as usize);
    let mut taken = rec.get_ref().len();
    for t in 0..ticks {
        let a = t as f32 * 0.02;
        let hand = Pose { position: Vec3::new(0.3 * a.cos(), 1.2, 0.3 * a.sin()), rotation: Quat::from_rotation_x(-0.6 + 0.2 * (a * 0.7).sin()) };
        let head = Pose { position: Vec3::new(0.0, 1.6, 0.0), rotation: Quat::from_rotation_y(0.3 * (a * 0.5).sin()) };
        let mut events = vec![InputEvent::ControllerPose { pose: hand }, InputEvent::HeadPose { pose: head }];
        match t % 120 {
            60 => events.push(InputEvent::ButtonDown { button: Button::Trigger }),
            66 => events.push(InputEvent::ButtonUp { button: Button::Trigger }),
            _ => {}
        }
        for e in &events {
            rec.event(t, (t as f64 * 1000.0 / 60.0).round() as u64, t, e).map_err(fail)?;
        }
        sim.step_with(events).map_err(|e| ClientError::Local(e.to_string()))?;
        rec.after_step(&sim).map_err(fail)?;
        if t + 1 == ticks {
            rec.flush().map_err(fail)?;
            break;
        }
        let now = rec.get_ref().len();
        batches.push((taken, now));
        taken = now;
    }
    rec.finish(&sim, json!({})).map_err(fail)?;
    batches.push((taken, out.len()));
    let first = out.iter().position(|&b| b == b'\n').map_or(0, |i| i + 1);
    let bytes = Bytes::from(out);
    let batches = batches.into_iter().map(|(a, b)| bytes.slice(a.max(first)..b)).collect();
    Ok((header, batches))
}

/// The server process and what it printed.
pub struct Server {
    /// The process.
    pub child: Child,
    /// The URL it printed.
    pub url: String,
}

/// Starts `grove serve` on loopback (any free port) on `dir`, as its own process, verifying
/// sessions as they stream or not (`--live`); returns once it listens.
pub fn start_server(grove: &Path, dir: &Path, live: bool) -> Result<Server, ClientError> {
    let mut child = Command::new(grove)
        .args(["serve", "--port", "0", "--abandon-after", "3600", "--max-sessions", "10000", "--live", if live { "on" } else { "off" }, "--out"])
        .arg(dir)
        .stdout(Stdio::piped())
        .stderr(Stdio::inherit())
        .spawn()
        .map_err(|e| ClientError::Local(format!("cannot start {}: {e}", grove.display())))?;
    let stdout = child.stdout.take().ok_or_else(|| ClientError::Local("no output from the server".into()))?;
    let mut lines = BufReader::new(stdout).lines();
    let url = loop {
        match lines.next() {
            Some(Ok(l)) => {
                if let Some(u) = l.split("listening on ").nth(1) {
                    break u.trim().to_string();
                }
            }
            _ => {
                let _ = child.kill();
                return Err(ClientError::Local("the server ended before it listened".into()));
            }
        }
    };
    // Keep reading its log so that it never blocks on a full pipe.
    std::thread::spawn(move || for _ in lines.by_ref() {});
    Ok(Server { child, url })
}

/// CPU seconds (user + system) and resident memory (MiB) of a process, from `/proc`.
fn sample(pid: u32) -> Option<(f64, f64)> {
    let stat = grove_systems::files::read_text(Path::new(&format!("/proc/{pid}/stat")), grove_systems::files::Kind::Status).ok()?;
    // Fields after the command's closing parenthesis: state is field 3, utime 14, stime 15.
    let rest = &stat[stat.rfind(')')? + 2..];
    let f: Vec<&str> = rest.split_whitespace().collect();
    // SAFETY: sysconf has no preconditions.
    let hz = unsafe { libc::sysconf(libc::_SC_CLK_TCK) }.max(1) as f64;
    let cpu = (f.get(11)?.parse::<f64>().ok()? + f.get(12)?.parse::<f64>().ok()?) / hz;
    let status = grove_systems::files::read_text(Path::new(&format!("/proc/{pid}/status")), grove_systems::files::Kind::Status).ok()?;
    let kb: f64 = status.lines().find_map(|l| l.strip_prefix("VmRSS:"))?.split_whitespace().next()?.parse().ok()?;
    Some((cpu, kb / 1024.0))
}

/// Runs the benchmark and returns its figures as JSON.
pub async fn bench(options: &BenchOptions, say: &dyn Fn(&str)) -> Result<serde_json::Value, ClientError> {
    let ticks = (options.seconds * 60.0).round().max(2.0) as u64;
    say(&format!("making a {ticks}-tick recording"));
    let (header, batches) = recording(ticks)?;
    let batches = Arc::new(batches);
    let dir = std::env::temp_dir().join(format!("grove-serve-bench-{}", std::process::id()));
    let (mut server, endpoint) = match &options.to {
        Some(to) => (None, to.clone()),
        None => {
            let _ = std::fs::remove_dir_all(&dir);
            let server = start_server(&options.grove, &dir, options.live)?;
            let endpoint = Endpoint::parse(&server.url, None)?;
            (Some(server), endpoint)
        }
    };
    let pid = server.as_ref().map(|s| s.child.id());
    say(&format!("{} sessions for {:.0} s against {}", options.sessions, options.seconds, endpoint.shown()));
    let start = Instant::now();
    let sampler = tokio::spawn(async move {
        let mut samples = Vec::new();
        let mut every = tokio::time::interval(Duration::from_secs(1));
        while let Some(pid) = pid {
            every.tick().await;
            match sample(pid) {
                Some((cpu, rss)) => samples.push((start.elapsed().as_secs_f64(), cpu, rss)),
                None => break,
            }
        }
        samples
    });
    let checkpoints = Checkpoints::default();
    let watcher = tokio::spawn(watch_live(endpoint.clone(), checkpoints.clone()));
    let mut tasks = Vec::new();
    for i in 0..options.sessions {
        let (endpoint, batches, checkpoints) = (endpoint.clone(), batches.clone(), checkpoints.clone());
        let mut h = header.clone();
        h.participant = Some(format!("B{:02}", i + 1));
        let header_line = encode_line(&Line::Header(h));
        // Sessions start spread over one tick, as independent headsets would.
        let offset = Duration::from_secs_f64(i as f64 / options.sessions as f64 / 60.0);
        tasks.push(tokio::spawn(async move { session(endpoint, header_line, batches, start, offset, checkpoints).await }));
    }
    let mut acks: Vec<(f64, f64)> = Vec::new();
    let mut statuses: Vec<Option<VerifyStatus>> = Vec::new();
    for t in tasks {
        let (a, status) = t.await.map_err(|e| ClientError::Local(e.to_string()))??;
        acks.extend(a);
        statuses.push(status);
    }
    let wall = start.elapsed().as_secs_f64();
    watcher.abort();
    let live = checkpoints.figures();
    if let Some(server) = server.as_mut() {
        // SAFETY: kill with a valid signal on the child we started.
        unsafe {
            libc::kill(server.child.id() as i32, libc::SIGTERM);
        }
        let _ = server.child.wait();
        let _ = std::fs::remove_dir_all(&dir);
    }
    let samples = sampler.await.unwrap_or_default();

    let mut all: Vec<f64> = acks.iter().map(|a| a.1).collect();
    all.sort_by(f64::total_cmp);
    let minutes = (wall / 60.0).ceil().max(1.0) as usize;
    let mut over_time = Vec::new();
    for m in 0..minutes {
        let (a, b) = (m as f64 * 60.0, (m + 1) as f64 * 60.0);
        let inside: Vec<&(f64, f64, f64)> = samples.iter().filter(|s| s.0 >= a && s.0 < b).collect();
        let mut lat: Vec<f64> = acks.iter().filter(|x| x.0 >= a && x.0 < b).map(|x| x.1).collect();
        lat.sort_by(f64::total_cmp);
        if inside.len() < 2 {
            continue;
        }
        let (first, last) = (inside[0], inside[inside.len() - 1]);
        let cpu = (last.1 - first.1) / (last.0 - first.0) * 100.0;
        let rss = inside.iter().map(|s| s.2).sum::<f64>() / inside.len() as f64;
        over_time.push(json!({ "minute": m + 1, "server_cpu_percent": round(cpu, 1), "server_rss_mib": round(rss, 1), "ack_ms_p50": round(quantile(&lat, 0.5), 2), "ack_ms_p99": round(quantile(&lat, 0.99), 2), "requests": lat.len() }));
    }
    let cpu_total = match (samples.first(), samples.last()) {
        (Some(f), Some(l)) if l.0 > f.0 => (l.1 - f.1) / (l.0 - f.0) * 100.0,
        _ => f64::NAN,
    };
    let verified = statuses.iter().filter(|s| **s == Some(VerifyStatus::Verified)).count();
    let (samples_max, cpu_total) = if samples.is_empty() { (None, None) } else { (Some(round(samples.iter().map(|s| s.2).fold(0.0, f64::max), 1)), Some(round(cpu_total, 1))) };
    Ok(json!({
        "serve": {
            "server": if options.to.is_some() { endpoint.shown() } else { "its own, on loopback".to_string() },
            "live_verification": match (&options.to, options.live) {
                (Some(_), _) => "the server's",
                (None, true) => "on",
                (None, false) => "off",
            },
            "live_checkpoints_verified": live.verified,
            "live_verify_ms_p50": live.p50,
            "live_verify_ms_p99": live.p99,
            "live_verify_ms_max": live.max,
            "live_wrong": live.wrong,
            "sessions": options.sessions,
            "seconds": options.seconds,
            "requests": all.len(),
            "requests_per_second": round(all.len() as f64 / wall, 0),
            "ack_ms_p50": round(quantile(&all, 0.5), 2),
            "ack_ms_p99": round(quantile(&all, 0.99), 2),
            "ack_ms_max": round(all.last().copied().unwrap_or(f64::NAN), 2),
            "server_cpu_percent": cpu_total,
            "server_rss_mib_max": samples_max,
            "sessions_verified": verified,
        },
        "serve_over_time": over_time,
    }))
}

/// One session: opened, each tick's lines sent on time, ended. Returns (seconds since the start,
/// acknowledgement ms) per request and the verification's status.
async fn session(endpoint: Endpoint, header: String, batches: Arc<Vec<Bytes>>, start: Instant, offset: Duration, checkpoints: Checkpoints) -> Result<(Vec<(f64, f64)>, Option<VerifyStatus>), ClientError> {
    let timeout = Duration::from_secs(10);
    let mut conn = endpoint.connect(timeout).await?;
    let (status, v) = conn.request(Method::POST, "/api/sessions", Bytes::from(json!({ "header": header }).to_string()), timeout).await?;
    if status != 201 {
        return Err(ClientError::Refused { what: "open".into(), status, reason: v.to_string() });
    }
    let id = v["session"].as_str().unwrap_or("").to_string();
    let file = v["file"].as_str().unwrap_or("").to_string();
    let mut acks = Vec::with_capacity(batches.len());
    let mut from = 2u64;
    let begin = tokio::time::Instant::now() + offset;
    for (t, batch) in batches.iter().enumerate() {
        tokio::time::sleep_until(begin + Duration::from_secs_f64(t as f64 / 60.0)).await;
        let sent = Instant::now();
        let (status, v) = conn.request(Method::POST, &format!("/api/sessions/{id}/lines?from={from}"), batch.clone(), timeout).await?;
        let ms = sent.elapsed().as_secs_f64() * 1000.0;
        if status != 200 {
            return Err(ClientError::Refused { what: "lines".into(), status, reason: v.to_string() });
        }
        from = v["acked"].as_u64().unwrap_or(0) + 1;
        acks.push((sent.duration_since(start).as_secs_f64(), ms));
        // Tick t's request ends with the checkpoint of tick t + 1 every second.
        let tick = t as u64 + 1;
        if tick % CHECKPOINT_EVERY == 0 {
            checkpoints.acked(&file, tick);
        }
    }
    let (_, v) = conn.request(Method::POST, &format!("/api/sessions/{id}/end"), Bytes::new(), Duration::from_secs(60)).await?;
    Ok((acks, serde_json::from_value(v["verification"]["status"].clone()).ok()))
}
