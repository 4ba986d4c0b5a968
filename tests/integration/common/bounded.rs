//! Running `grove` with a watchdog, measuring its wall time and peak memory: the bounds every
//! hostile input must stay within (exit 2, one line, 2 s, 200 MB).

use std::path::Path;
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use super::{assert_one_line_error, root};

/// The time and memory every corpus input must stay within.
pub const TIME_BOUND: Duration = Duration::from_secs(2);
pub const MEMORY_BOUND_KB: i64 = 200 * 1024;


/// Runs `grove` with a wall-clock watchdog (10 s, then it is killed) and returns its output,
/// wall time and peak resident memory in KiB (from `wait4`).
pub fn grove_bounded(args: &[&str]) -> (Output, Duration, i64) {
    let start = Instant::now();
    let mut child = Command::new(env!("CARGO_BIN_EXE_grove"))
        .args(args)
        .current_dir(root())
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the grove binary runs");
    let pid = child.id() as libc::pid_t;
    let (mut out, mut err) = (child.stdout.take().unwrap(), child.stderr.take().unwrap());
    let out_reader = std::thread::spawn(move || {
        let mut v = Vec::new();
        std::io::Read::read_to_end(&mut out, &mut v).ok();
        v
    });
    let err_reader = std::thread::spawn(move || {
        let mut v = Vec::new();
        std::io::Read::read_to_end(&mut err, &mut v).ok();
        v
    });
    let mut status = 0;
    // SAFETY: an all-zero `rusage` is a valid value of this plain C struct.
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    loop {
        // SAFETY: `pid` is our own child, not yet reaped; `status` and `usage` are valid for writes.
        let r = unsafe { libc::wait4(pid, &mut status, libc::WNOHANG, &mut usage) };
        if r == pid {
            break;
        }
        assert!(r == 0, "wait4 failed");
        if start.elapsed() > Duration::from_secs(10) {
            let _ = child.kill();
            panic!("grove {args:?} ran for more than 10 s: a hang");
        }
        std::thread::sleep(Duration::from_millis(5));
    }
    let took = start.elapsed();
    let code = if libc::WIFEXITED(status) { libc::WEXITSTATUS(status) } else { 128 + libc::WTERMSIG(status) };
    use std::os::unix::process::ExitStatusExt;
    let output = Output { status: std::process::ExitStatus::from_raw(code << 8), stdout: out_reader.join().unwrap(), stderr: err_reader.join().unwrap() };
    (output, took, usage.ru_maxrss)
}

/// Asserts exit 2, one line naming `needle`, and the time and memory bounds.
pub fn refused_within_bounds(args: &[&str], needle: &str) {
    let (out, took, rss_kb) = grove_bounded(args);
    assert_one_line_error(&out, 2, needle);
    assert!(took < TIME_BOUND, "grove {args:?} took {took:?}");
    assert!(rss_kb < MEMORY_BOUND_KB, "grove {args:?} used {} MB", rss_kb / 1024);
}


/// Every file below `dir` (relative paths, sorted), to check that a refused command wrote nothing.
pub fn listing(dir: &Path) -> Vec<String> {
    fn walk(base: &Path, d: &Path, out: &mut Vec<String>) {
        let Ok(entries) = std::fs::read_dir(d) else { return };
        for e in entries.flatten() {
            let p = e.path();
            out.push(p.strip_prefix(base).unwrap().display().to_string());
            if p.is_dir() && !p.is_symlink() {
                walk(base, &p, out);
            }
        }
    }
    let mut out = Vec::new();
    walk(dir, dir, &mut out);
    out.sort();
    out
}

/// [`refused_within_bounds`], and the folder `dir` holds exactly what it held before.
pub fn refused_writing_nothing(args: &[&str], needle: &str, dir: &Path) {
    let before = listing(dir);
    refused_within_bounds(args, needle);
    assert_eq!(listing(dir), before, "grove {args:?} left files behind in {}", dir.display());
}
