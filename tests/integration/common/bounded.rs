//! Running `grove` with a watchdog, measuring its wall time and peak memory: the bounds every
//! hostile input must stay within (exit 2, one line, 2 s, 200 MB).

use std::path::Path;
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use super::{assert_one_line_error, root};

/// The time and memory every corpus input must stay within.
pub const TIME_BOUND: Duration = Duration::from_secs(2);
pub const MEMORY_BOUND_KB: i64 = 200 * 1024;

/// The small parent that runs `grove` and reports its peak memory and wall time. Linux records
/// the address space a process leaves at `exec` in its peak: a child spawned straight from this
/// test process (one binary holding every integration test, renderers included) would start at the
/// test process's own peak, hundreds of MB. A child of this small Python process starts at its
/// few MB, so `RUSAGE_CHILDREN` here is grove's own peak.
const MEASURE: &str = r#"
import resource, subprocess, sys, time
t = time.monotonic_ns()
r = subprocess.run(sys.argv[2:])
t = time.monotonic_ns() - t
with open(sys.argv[1], "w") as f:
    f.write("%d %d" % (resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss, t))
sys.exit(r.returncode if r.returncode >= 0 else 128 - r.returncode)
"#;

/// Runs `grove` with a wall-clock watchdog (10 s, then it and its parent are killed) and returns
/// its output, wall time and peak resident memory in KiB, both measured by the small parent
/// [`MEASURE`] (from `wait4`'s usage of its one child).
pub fn grove_bounded(args: &[&str]) -> (Output, Duration, i64) {
    use std::os::unix::process::CommandExt;
    let report = tempfile::NamedTempFile::new().expect("a temporary file");
    let start = Instant::now();
    let python = std::env::var("GROVE_PYTHON").unwrap_or_else(|_| "python3".into());
    let mut child = Command::new(python)
        .arg("-c")
        .arg(MEASURE)
        .arg(report.path())
        .arg(env!("CARGO_BIN_EXE_grove"))
        .args(args)
        .current_dir(root())
        .process_group(0)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("python3 runs (it measures grove's peak memory)");
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
    let status = loop {
        if let Some(status) = child.try_wait().expect("waiting for the measuring parent") {
            break status;
        }
        if start.elapsed() > Duration::from_secs(10) {
            // SAFETY: a plain kill of the process group this test made for its child.
            unsafe { libc::kill(-pid, libc::SIGKILL) };
            let _ = child.wait();
            panic!("grove {args:?} ran for more than 10 s: a hang");
        }
        std::thread::sleep(Duration::from_millis(5));
    };
    let measured = std::fs::read_to_string(report.path()).unwrap_or_default();
    let mut fields = measured.split_whitespace().map(|v| v.parse::<i64>().unwrap_or(-1));
    let (rss_kb, took_ns) = (fields.next().unwrap_or(-1), fields.next().unwrap_or(-1));
    assert!(
        rss_kb > 0 && took_ns > 0,
        "the measuring parent reported nothing for grove {args:?} ({measured:?}, {status})"
    );
    let output = Output { status, stdout: out_reader.join().unwrap(), stderr: err_reader.join().unwrap() };
    (output, Duration::from_nanos(took_ns as u64), rss_kb)
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
