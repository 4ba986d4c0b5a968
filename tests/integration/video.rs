//! `grove render --replay FILE --video OUT.mp4`: ffprobe (Debian's ffmpeg) reads the file as
//! H.264 with the frames and duration the arguments ask for; a frame decoded by ffmpeg matches
//! `grove render --replay FILE --tick T` of the same tick; every camera writes a video; ghosts
//! are the other recordings of the task, each where its own replay puts it at the same time
//! since its task started; bad arguments give one line, exit 2 and leave no file.

use crate::common;

use std::path::Path;
use std::process::Command;

use common::bounded::refused_writing_nothing;
use common::{grove, root};
use grove_systems::replay::{Player, ReplayOptions, replay_file};

const P01: &str = "replays/study/P01-ray-casting-7.jsonl";

fn ffprobe(file: &Path, entries: &str) -> String {
    let out = Command::new("ffprobe")
        .args([
            "-v",
            "error",
            "-count_frames",
            "-select_streams",
            "v:0",
            "-show_entries",
            entries,
            "-of",
            "default=nw=1",
        ])
        .arg(file)
        .output()
        .expect("ffprobe runs (scripts/test installs Debian's ffmpeg)");
    assert!(out.status.success(), "ffprobe failed: {}", String::from_utf8_lossy(&out.stderr));
    String::from_utf8_lossy(&out.stdout).into_owned()
}

fn value<'a>(probe: &'a str, key: &str) -> &'a str {
    probe.lines().find_map(|l| l.strip_prefix(&format!("{key}="))).unwrap_or_else(|| panic!("no {key} in {probe}"))
}

fn run_ok(args: &[&str]) -> String {
    let out = grove(args);
    assert!(out.status.success(), "grove {args:?}: {}", String::from_utf8_lossy(&out.stderr));
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// Frame `n` (0-based) of a video, decoded by ffmpeg to RGB.
fn decoded_frame(video: &Path, n: u32, png: &Path) -> image::RgbImage {
    let out = Command::new("ffmpeg")
        .args(["-v", "error", "-y", "-i"])
        .arg(video)
        .args(["-vf", &format!("select=eq(n\\,{n})"), "-frames:v", "1"])
        .arg(png)
        .output()
        .expect("ffmpeg runs");
    assert!(out.status.success(), "ffmpeg failed: {}", String::from_utf8_lossy(&out.stderr));
    image::open(png).unwrap().to_rgb8()
}

/// Mean absolute difference per channel, 0–255, over rows `y0..y1`.
fn mean_abs(a: &image::RgbImage, b: &image::RgbImage, y0: u32, y1: u32) -> f64 {
    assert_eq!(a.dimensions(), b.dimensions());
    let mut sum = 0u64;
    for y in y0..y1 {
        for x in 0..a.width() {
            let (p, q) = (a.get_pixel(x, y), b.get_pixel(x, y));
            sum += (0..3).map(|c| (p[c] as i32 - q[c] as i32).unsigned_abs() as u64).sum::<u64>();
        }
    }
    sum as f64 / ((y1 - y0) as f64 * a.width() as f64 * 3.0)
}

#[test]
fn ffprobe_reads_h264_with_the_asked_frames_and_duration() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("p01.mp4");
    let o = out.display().to_string();
    // The task starts at tick 31 (the recording's start_task event); 300 ticks at 60 Hz are
    // 5 s: 150 frames at 30 fps, and 75 at twice the speed.
    run_ok(&[
        "render",
        "--replay",
        P01,
        "--video",
        &o,
        "--from",
        "task-start",
        "--to",
        "331",
        "--width",
        "320",
        "--height",
        "180",
    ]);
    let p = ffprobe(&out, "stream=codec_name,width,height,nb_read_frames,r_frame_rate,duration");
    assert_eq!(value(&p, "codec_name"), "h264");
    assert_eq!((value(&p, "width"), value(&p, "height")), ("320", "180"));
    assert_eq!(value(&p, "nb_read_frames"), "150");
    assert_eq!(value(&p, "r_frame_rate"), "30/1");
    let duration: f64 = value(&p, "duration").parse().unwrap();
    assert!((duration - 5.0).abs() < 0.05, "duration {duration}");

    let fast = dir.path().join("fast.mp4");
    run_ok(&[
        "render",
        "--replay",
        P01,
        "--video",
        &fast.display().to_string(),
        "--from",
        "31",
        "--to",
        "331",
        "--speed",
        "2",
        "--fps",
        "24",
        "--width",
        "160",
        "--height",
        "90",
    ]);
    let p = ffprobe(&fast, "stream=nb_read_frames,r_frame_rate");
    // 5 s of the task at twice the speed is 2.5 s of video: 60 frames at 24 fps.
    assert_eq!((value(&p, "nb_read_frames"), value(&p, "r_frame_rate")), ("60", "24/1"));
    // Nothing but the video is left in the folder.
    let mut names: Vec<String> =
        std::fs::read_dir(dir.path()).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    names.sort();
    assert_eq!(names, ["fast.mp4", "p01.mp4"]);
}

#[test]
fn a_decoded_frame_matches_the_still_of_its_tick() {
    let dir = tempfile::tempdir().unwrap();
    let video = dir.path().join("v.mp4");
    // From tick 600, two ticks a frame: frame 15 shows tick 630.
    run_ok(&[
        "render",
        "--replay",
        P01,
        "--video",
        &video.display().to_string(),
        "--from",
        "600",
        "--to",
        "700",
        "--width",
        "320",
        "--height",
        "180",
    ]);
    let still = dir.path().join("still.png");
    run_ok(&[
        "render",
        "--replay",
        P01,
        "--tick",
        "630",
        "--out",
        &still.display().to_string(),
        "--width",
        "320",
        "--height",
        "180",
    ]);
    let still = image::open(&still).unwrap().to_rgb8();
    let frame = decoded_frame(&video, 15, &dir.path().join("f15.png"));
    // The captions cover the top and bottom rows; between them is the world as rendered.
    let (top, bottom) = grove::video::captions::covered_rows(180);
    let same = mean_abs(&frame, &still, top, 180 - bottom);
    // H.264's loss at this size is about 4 of 255 per channel, more or less with the picture's
    // detail (4.04 on the recording of the moved sixth target); a wrong tick adds to it.
    assert!(same < 4.5, "frame 15 differs from the still of tick 630 by {same:.2} per channel");
    // A frame a second later shows another moment: further from the still than the coding loss.
    let later = decoded_frame(&video, 45, &dir.path().join("f45.png"));
    let other = mean_abs(&later, &still, top, 180 - bottom);
    assert!(
        other > same,
        "tick 690 ({other:.2}) should differ more from tick 630's still than tick 630's frame ({same:.2})"
    );
    // The captions are there: the top rows differ from the still.
    assert!(mean_abs(&frame, &still, 0, top) > 2.0 * same);
}

#[test]
fn every_camera_writes_a_video_and_they_differ() {
    let dir = tempfile::tempdir().unwrap();
    let mut frames = Vec::new();
    for camera in ["head", "shoulder", "top", "orbit"] {
        let video = dir.path().join(format!("{camera}.mp4"));
        run_ok(&[
            "render",
            "--replay",
            P01,
            "--video",
            &video.display().to_string(),
            "--camera",
            camera,
            "--from",
            "900",
            "--to",
            "920",
            "--width",
            "160",
            "--height",
            "90",
            "--ghosts",
            "replays/study",
        ]);
        assert_eq!(value(&ffprobe(&video, "stream=nb_read_frames"), "nb_read_frames"), "10");
        frames.push(decoded_frame(&video, 5, &dir.path().join(format!("{camera}.png"))));
    }
    for i in 0..frames.len() {
        for j in i + 1..frames.len() {
            assert!(mean_abs(&frames[i], &frames[j], 0, 90) > 3.0, "cameras {i} and {j} show the same picture");
        }
    }
}

#[test]
fn ghosts_are_the_other_recordings_of_the_task_aligned_at_its_start() {
    let p01 = root().join(P01);
    let chosen = Player::open(&p01, &[], &Default::default()).unwrap();
    let start = chosen.task_start_tick().unwrap();
    let mut ghosts = grove::video::ghosts::open(
        &root().join("replays/study"),
        &p01,
        chosen.header.task.as_deref(),
        Some(start),
        &Default::default(),
    )
    .unwrap();
    let names: Vec<&str> = ghosts.iter().map(|g| g.participant.as_str()).collect();
    let expected: Vec<String> = (2..=12).map(|i| format!("P{i:02}")).collect();
    assert_eq!(names, expected, "the other participants' ray-casting recordings, not the manual ones");
    // P05, 400 ticks after the chosen task start: its own replay 400 ticks after its own start.
    let p05 = ghosts.iter_mut().find(|g| g.participant == "P05").unwrap();
    let figure = p05.figure_at(start + 400);
    let path = root().join("replays/study/P05-ray-casting-7.jsonl");
    let own_start = Player::open(&path, &[], &Default::default()).unwrap().task_start_tick().unwrap();
    let own = replay_file(&path, &ReplayOptions { until: Some(own_start + 400), ..Default::default() }).unwrap();
    let head = own.sim.head().pose;
    assert_eq!((figure.head, figure.head_rotation), (head.position, head.rotation));
    assert!(!figure.solid);
    assert_eq!(figure.color, grove::video::ghosts::participant_color("P05"));
}

#[test]
fn bad_arguments_give_one_line_and_leave_no_file() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.mp4").display().to_string();
    let d = dir.path();
    refused_writing_nothing(
        &["render", "--replay", P01, "--video", &out, "--width", "321", "--height", "180"],
        "must be even",
        d,
    );
    refused_writing_nothing(&["render", "--replay", P01, "--video", &out, "--fps", "29.97"], "--fps", d);
    refused_writing_nothing(&["render", "--replay", P01, "--video", &out, "--fps", "0"], "--fps", d);
    refused_writing_nothing(&["render", "--replay", P01, "--video", &out, "--speed", "0"], "--speed", d);
    refused_writing_nothing(
        &["render", "--replay", P01, "--video", &out, "--to", "999999"],
        "past the recording's end",
        d,
    );
    refused_writing_nothing(
        &["render", "--replay", P01, "--video", &out, "--from", "500", "--to", "400"],
        "must come before",
        d,
    );
    refused_writing_nothing(&["render", "--replay", P01, "--video", &out, "--from", "soon"], "task mark", d);
    refused_writing_nothing(
        &["render", "--replay", P01, "--video", &out, "--ghosts", "replays/study/P02-manual-7.jsonl"],
        "--ghosts needs a folder",
        d,
    );
    refused_writing_nothing(
        &["render", "--replay", P01, "--video", &dir.path().join("x.avi").display().to_string()],
        ".mp4",
        d,
    );
    refused_writing_nothing(
        &["render", "--replay", "tests/hostile/footer-final-tick-1e12.jsonl", "--video", &out],
        "past the limit",
        d,
    );
    refused_writing_nothing(&["render", "--scene", "assets/scenes/study.ron", "--video", &out], "--replay", d);
    // An existing file is kept as it was without --force.
    std::fs::write(dir.path().join("keep.mp4"), b"not a video").unwrap();
    let keep = dir.path().join("keep.mp4").display().to_string();
    refused_writing_nothing(&["render", "--replay", P01, "--video", &keep, "--to", "60"], "already exists", d);
    assert_eq!(std::fs::read(dir.path().join("keep.mp4")).unwrap(), b"not a video");
}
