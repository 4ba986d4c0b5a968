//! A real window under Xvfb: `grove play --record FILE`, a click on the ground with xdotool,
//! Escape to quit, then `grove replay FILE --json` must verify the recording and re-simulate
//! the planted tree. This proves that input from a real window replays exactly.
//!
//! Needs `Xvfb` and `xdotool` (Debian: `xvfb xdotool`) and a Vulkan or GL driver (lavapipe from
//! `mesa-vulkan-drivers`). A missing tool fails the test with a message saying what to install.

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

const GROVE: &str = env!("CARGO_BIN_EXE_grove");

/// Child processes that are killed when the test ends, however it ends.
struct Kill(Vec<Child>);

impl Drop for Kill {
    fn drop(&mut self) {
        for c in self.0.iter_mut().rev() {
            let _ = c.kill();
            let _ = c.wait();
        }
    }
}

fn have(tool: &str) -> bool {
    Command::new("sh").arg("-c").arg(format!("command -v {tool}")).stdout(Stdio::null()).status().is_ok_and(|s| s.success())
}

/// Starts Xvfb on a free display number and waits for its socket.
fn start_xvfb() -> (Child, String) {
    assert!(have("Xvfb"), "Xvfb is not installed; install it (Debian: apt-get install xvfb) to run the window test");
    assert!(have("xdotool"), "xdotool is not installed; install it (Debian: apt-get install xdotool) to run the window test");
    let base = 99 + (std::process::id() % 300);
    for n in base..base + 200 {
        let socket = PathBuf::from(format!("/tmp/.X11-unix/X{n}"));
        let lock = PathBuf::from(format!("/tmp/.X{n}-lock"));
        if socket.exists() || lock.exists() {
            continue;
        }
        let child = Command::new("Xvfb")
            .arg(format!(":{n}"))
            .args(["-screen", "0", "1280x720x24", "-nolisten", "tcp"])
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .expect("cannot start Xvfb");
        let start = Instant::now();
        while start.elapsed() < Duration::from_secs(15) {
            if socket.exists() {
                return (child, format!(":{n}"));
            }
            std::thread::sleep(Duration::from_millis(100));
        }
        let mut child = child;
        let _ = child.kill();
        let _ = child.wait();
    }
    panic!("could not start Xvfb on any display from :{base}");
}

fn xdotool(display: &str, args: &[&str]) -> String {
    let out = Command::new("timeout")
        .arg("60")
        .arg("xdotool")
        .args(args)
        .env("DISPLAY", display)
        .output()
        .expect("cannot run xdotool");
    assert!(out.status.success(), "xdotool {args:?} failed: {}", String::from_utf8_lossy(&out.stderr));
    String::from_utf8_lossy(&out.stdout).trim().to_string()
}

fn wait_exit(child: &mut Child, limit: Duration) -> Option<std::process::ExitStatus> {
    let start = Instant::now();
    while start.elapsed() < limit {
        if let Ok(Some(status)) = child.try_wait() {
            return Some(status);
        }
        std::thread::sleep(Duration::from_millis(100));
    }
    None
}

fn runtime_dir(dir: &Path) -> PathBuf {
    let d = dir.join("xdg");
    std::fs::create_dir_all(&d).unwrap();
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(&d, std::fs::Permissions::from_mode(0o700)).unwrap();
    }
    d
}

#[test]
fn a_click_in_a_real_window_plants_a_tree_that_replays_exactly() {
    let dir = tempfile::tempdir().unwrap();
    let record = dir.path().join("session.jsonl");
    let (xvfb, display) = start_xvfb();
    let mut kill = Kill(vec![xvfb]);

    let log = std::fs::File::create(dir.path().join("play.log")).unwrap();
    let play = Command::new(GROVE)
        .args(["play", "--free", "--participant", "XVFB", "--record"])
        .arg(&record)
        .env("DISPLAY", &display)
        .env("XDG_RUNTIME_DIR", runtime_dir(dir.path()))
        .env_remove("WAYLAND_DISPLAY")
        .stdout(Stdio::null())
        .stderr(log)
        .spawn()
        .expect("cannot start grove play");
    let pid = play.id().to_string();
    kill.0.push(play);

    let wid = xdotool(&display, &["search", "--sync", "--onlyvisible", "--pid", &pid]);
    let wid = wid.lines().next().expect("no window").to_string();
    // The first frames on a software GPU take a while; give the app time to draw and to
    // start reading input.
    std::thread::sleep(Duration::from_secs(6));
    xdotool(&display, &["mousemove", "--window", &wid, "630", "560"]);
    std::thread::sleep(Duration::from_millis(500));
    xdotool(&display, &["mousemove", "--window", &wid, "640", "560"]);
    std::thread::sleep(Duration::from_millis(700));
    xdotool(&display, &["click", "1"]);
    std::thread::sleep(Duration::from_millis(1500));
    xdotool(&display, &["windowfocus", "--sync", &wid]);
    xdotool(&display, &["key", "Escape"]);

    let play = kill.0.last_mut().unwrap();
    let status = wait_exit(play, Duration::from_secs(60));
    let stderr = std::fs::read_to_string(dir.path().join("play.log")).unwrap_or_default();
    let status = status.unwrap_or_else(|| panic!("grove play did not quit on Escape; its stderr: {stderr}"));
    assert!(status.success(), "grove play failed: {status}; its stderr: {stderr}");

    let out = Command::new(GROVE).args(["replay", "--json"]).arg(&record).output().unwrap();
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap_or_else(|e| panic!("replay JSON: {e}; stderr {}", String::from_utf8_lossy(&out.stderr)));
    assert_eq!(out.status.code(), Some(0), "replay: {report}");
    assert_eq!(report["verified"], true, "{report}");
    assert_eq!(report["complete"], true, "the recording has its footer: {report}");
    assert_eq!(report["participant"], "XVFB");
    assert_eq!(report["synthetic"], false);
    assert!(report["events"]["button_down"].as_u64().unwrap_or(0) >= 1, "the click was recorded: {report}");
    assert!(report["events"]["controller_pose"].as_u64().unwrap_or(0) >= 1, "the cursor ray was recorded: {report}");

    // The verified final hash covers every tree, so the footer's tree count is the
    // re-simulated one: the study scene's two trees plus the planted one.
    let text = std::fs::read_to_string(&record).unwrap();
    let footer: serde_json::Value = serde_json::from_str(text.lines().last().unwrap()).unwrap();
    assert_eq!(footer["type"], "footer");
    assert_eq!(footer["summary"]["trees"], 3, "one tree was planted: {footer}");
    // The one click is the only Trigger press in the file.
    let planted = text.lines().filter(|l| l.contains("\"button_down\"") && l.contains("\"trigger\"")).count();
    assert_eq!(planted, 1, "exactly one Trigger press");
}
