//! Real windows under Xvfb, driven by xdotool as a person would (pointer moves and clicks at
//! screen positions; without a window manager the window sits at the screen's top left):
//!
//! - a click on the ground plants a tree, and the recording replays exactly;
//! - clicks on menu items (a tree button, "Finish task") never reach the scene as Trigger, the
//!   task's time stops at "Finish task", Escape asks before quitting, and the result `grove play`
//!   prints agrees with `grove replay --json` and `grove study`;
//! - the window destroyed from outside (`xdotool windowclose`) still leaves a complete recording
//!   and a clean exit.
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
    Command::new("sh")
        .arg("-c")
        .arg(format!("command -v {tool}"))
        .stdout(Stdio::null())
        .status()
        .is_ok_and(|s| s.success())
}

/// Starts Xvfb on a free display number and waits for its socket.
fn start_xvfb() -> (Child, String) {
    assert!(have("Xvfb"), "Xvfb is not installed; install it (Debian: apt-get install xvfb) to run the window test");
    assert!(
        have("xdotool"),
        "xdotool is not installed; install it (Debian: apt-get install xdotool) to run the window test"
    );
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

/// One window at a time: on a small machine without a GPU, several software-rendered windows
/// at once make each too slow to start within the tests' waits.
static ONE_WINDOW: std::sync::Mutex<()> = std::sync::Mutex::new(());

fn one_window() -> std::sync::MutexGuard<'static, ()> {
    ONE_WINDOW.lock().unwrap_or_else(|e| e.into_inner())
}

/// Waits until the recording at `record` holds a checkpoint, that is until the session's clock
/// runs (which it does from the first drawn frame on), then a moment more.
fn wait_running(record: &Path) {
    let start = Instant::now();
    while start.elapsed() < Duration::from_secs(90) {
        if std::fs::read_to_string(record).is_ok_and(|t| t.contains("\"type\":\"checkpoint\"")) {
            std::thread::sleep(Duration::from_secs(2));
            return;
        }
        std::thread::sleep(Duration::from_millis(200));
    }
    panic!("grove play did not start its session within 90 s");
}

/// `grove play` started under `display` with `args`, its stderr going to `dir/play.log`; waits
/// for its window and returns its id.
fn start_play(display: &str, dir: &Path, args: &[&str], kill: &mut Kill) -> String {
    let log = std::fs::File::create(dir.join("play.log")).unwrap();
    let play = Command::new(GROVE)
        .arg("play")
        .args(args)
        .env("DISPLAY", display)
        .env("XDG_RUNTIME_DIR", runtime_dir(dir))
        .env_remove("WAYLAND_DISPLAY")
        .stdout(Stdio::null())
        .stderr(log)
        .spawn()
        .expect("cannot start grove play");
    let pid = play.id().to_string();
    kill.0.push(play);
    let wid = xdotool(display, &["search", "--sync", "--onlyvisible", "--pid", &pid]);
    wid.lines().next().expect("no window").to_string()
}

/// Waits for the last started `grove play` to exit and returns its exit status and stderr.
fn play_exit(dir: &Path, kill: &mut Kill, what: &str) -> (std::process::ExitStatus, String) {
    let play = kill.0.last_mut().unwrap();
    let status = wait_exit(play, Duration::from_secs(60));
    let stderr = std::fs::read_to_string(dir.join("play.log")).unwrap_or_default();
    let status = status.unwrap_or_else(|| panic!("grove play did not end after {what}; its stderr: {stderr}"));
    (status, stderr)
}

fn replay_json(record: &Path) -> serde_json::Value {
    let out = Command::new(GROVE).args(["replay", "--json"]).arg(record).output().unwrap();
    let report: serde_json::Value = serde_json::from_slice(&out.stdout)
        .unwrap_or_else(|e| panic!("replay JSON: {e}; stderr {}", String::from_utf8_lossy(&out.stderr)));
    assert_eq!(out.status.code(), Some(0), "replay: {report}");
    report
}

#[test]
fn a_click_in_a_real_window_plants_a_tree_that_replays_exactly() {
    let _one = one_window();
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
    wait_running(&record);
    xdotool(&display, &["mousemove", "--window", &wid, "630", "560"]);
    std::thread::sleep(Duration::from_millis(500));
    xdotool(&display, &["mousemove", "--window", &wid, "640", "560"]);
    std::thread::sleep(Duration::from_millis(700));
    xdotool(&display, &["click", "1"]);
    std::thread::sleep(Duration::from_millis(1500));
    xdotool(&display, &["windowfocus", "--sync", &wid]);
    // Escape asks for confirmation during a recording; Enter confirms.
    xdotool(&display, &["key", "Escape"]);
    std::thread::sleep(Duration::from_millis(800));
    xdotool(&display, &["key", "Return"]);

    let play = kill.0.last_mut().unwrap();
    let status = wait_exit(play, Duration::from_secs(60));
    let stderr = std::fs::read_to_string(dir.path().join("play.log")).unwrap_or_default();
    let status = status.unwrap_or_else(|| panic!("grove play did not quit on Escape and Enter; its stderr: {stderr}"));
    assert!(status.success(), "grove play failed: {status}; its stderr: {stderr}");

    let out = Command::new(GROVE).args(["replay", "--json"]).arg(&record).output().unwrap();
    let report: serde_json::Value = serde_json::from_slice(&out.stdout)
        .unwrap_or_else(|e| panic!("replay JSON: {e}; stderr {}", String::from_utf8_lossy(&out.stderr)));
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

/// Where the play window's widgets are at 1280 × 720 (egui points = pixels under Xvfb).
mod layout {
    /// The Trees window's conifer-billboard button (the Trees window opens at (10, 60)).
    pub const TREE_BUTTON: (u32, u32) = (105, 455);
    /// The task panel's "Finish task" button (the panel is on the right, under 7 targets).
    pub const FINISH_TASK: (u32, u32) = (1127, 262);
}

/// A quick hand: the pointer jumps to `(x, y)` and clicks at once, before the UI has drawn a
/// frame with the pointer there.
fn quick_click(display: &str, (x, y): (u32, u32)) {
    xdotool(display, &["mousemove", &x.to_string(), &y.to_string(), "click", "1"]);
}

#[test]
fn menu_clicks_never_pull_the_trigger_and_the_result_agrees_with_replay_and_study() {
    let dir = tempfile::tempdir().unwrap();
    let recordings = dir.path().join("recordings");
    std::fs::create_dir_all(&recordings).unwrap();
    let record = recordings.join("PX-ray-casting-7.jsonl");
    let _one = one_window();
    let (xvfb, display) = start_xvfb();
    let mut kill = Kill(vec![xvfb]);
    let wid = start_play(
        &display,
        dir.path(),
        &["--task", "ray-casting-7", "--participant", "PX", "--record", record.to_str().unwrap()],
        &mut kill,
    );
    wait_running(&record);

    // A quick click on a tree button in the always-visible Trees window, then a slow one.
    quick_click(&display, layout::TREE_BUTTON);
    std::thread::sleep(Duration::from_millis(800));
    xdotool(&display, &["mousemove", &(layout::TREE_BUTTON.0 + 4).to_string(), &layout::TREE_BUTTON.1.to_string()]);
    std::thread::sleep(Duration::from_millis(600));
    xdotool(&display, &["click", "1"]);
    std::thread::sleep(Duration::from_millis(800));
    // Finish the task, then linger: the task's time must not run on.
    quick_click(&display, layout::FINISH_TASK);
    std::thread::sleep(Duration::from_secs(3));

    // Escape asks first: the window stays open.
    xdotool(&display, &["windowfocus", "--sync", &wid]);
    xdotool(&display, &["key", "Escape"]);
    std::thread::sleep(Duration::from_millis(1500));
    let play = kill.0.last_mut().unwrap();
    assert!(play.try_wait().unwrap().is_none(), "Escape during a recording asks before quitting");
    // Enter confirms.
    xdotool(&display, &["key", "Return"]);
    let (status, stderr) = play_exit(dir.path(), &mut kill, "Escape and Enter");
    assert!(status.success(), "grove play failed: {status}; its stderr: {stderr}");
    let last = stderr.lines().last().unwrap_or_default();
    assert!(
        last.contains("recording saved to") && last.contains(record.to_str().unwrap()),
        "the last line says where the recording is: {stderr}"
    );

    let text = std::fs::read_to_string(&record).unwrap();
    let kinds = |kind: &str| text.lines().filter(|l| l.contains(&format!("\"{kind}\""))).count();
    assert_eq!(text.lines().filter(|l| l.contains("\"trigger\"")).count(), 0, "no Trigger from menu clicks:\n{text}");
    assert!(kinds("choose_model") >= 2, "both clicks on the tree button chose a model:\n{text}");
    assert_eq!(kinds("end_task"), 1, "Finish task was clicked");

    // The result the window printed is what grove replay and grove study report.
    let line = stderr
        .lines()
        .find(|l| l.starts_with("task ray-casting-7"))
        .unwrap_or_else(|| panic!("no result line: {stderr}"));
    let report = replay_json(&record);
    assert_eq!(report["verified"], true, "{report}");
    assert_eq!(report["complete"], true, "{report}");
    let task = &report["task"];
    let time = task["time_s"].as_f64().unwrap();
    assert_eq!(task["errors"], 0, "menu clicks made no errors: {report}");
    assert_eq!(line, format!("task ray-casting-7 (ray-casting): not completed, {time:.2} s, 0 trees, 0 errors"));
    // The time is the time of the end_task event (the task started at tick 0), not the end of
    // the file, which came later.
    let tick_of = |kind: &str| -> Option<u64> {
        text.lines()
            .filter_map(|l| serde_json::from_str::<serde_json::Value>(l).ok())
            .find(|v| v["event"]["kind"] == kind)
            .and_then(|v| v["tick"].as_u64())
    };
    let (start, end) = (tick_of("start_task").unwrap(), tick_of("end_task").unwrap());
    let dt = report["sim_seconds"].as_f64().unwrap() / report["ticks"].as_f64().unwrap();
    assert!(
        (time - (end - start) as f64 * dt).abs() < 1e-6,
        "the time stopped at Finish task: {time} s, end_task at tick {end}"
    );
    assert!(report["ticks"].as_u64().unwrap() > end + 10, "the session ran on after Finish task: {report}");

    let out = Command::new(GROVE)
        .args(["study", "--json", "--replays"])
        .arg(&recordings)
        .arg("--out")
        .arg(dir.path().join("study"))
        .output()
        .unwrap();
    assert!(out.status.success(), "study: {}", String::from_utf8_lossy(&out.stderr));
    let study: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let trial = &study["trials"][0]["task"];
    assert_eq!(trial["time_s"].as_f64(), Some(time), "{study}");
    assert_eq!(trial["errors"], 0, "{study}");
}

#[test]
fn a_window_destroyed_from_outside_leaves_a_complete_recording() {
    let dir = tempfile::tempdir().unwrap();
    let record = dir.path().join("closed.jsonl");
    let _one = one_window();
    let (xvfb, display) = start_xvfb();
    let mut kill = Kill(vec![xvfb]);
    let wid = start_play(&display, dir.path(), &["--free", "--record", record.to_str().unwrap()], &mut kill);
    wait_running(&record);
    xdotool(&display, &["mousemove", "700", "500"]);
    std::thread::sleep(Duration::from_millis(800));
    xdotool(&display, &["windowclose", &wid]);
    let (status, stderr) = play_exit(dir.path(), &mut kill, "xdotool windowclose");
    assert!(status.success(), "exit 0 when the window is destroyed: {status}; stderr: {stderr}");
    assert!(!stderr.contains("internal error") && !stderr.contains("panicked"), "no panic: {stderr}");
    let last = stderr.lines().last().unwrap_or_default();
    assert!(
        last.contains("recording saved to") && last.contains(record.to_str().unwrap()),
        "the last line says where the recording is: {stderr}"
    );
    let report = replay_json(&record);
    assert_eq!(report["verified"], true, "{report}");
    assert_eq!(report["complete"], true, "the recording has its footer: {report}");
}
