//! The mutation run of the surfaces added after the first hostile-input work (issue #32): scene
//! sections (grass, water, scatter, banks), L-system grammars and the models written from them,
//! aerial images and crowns tables, and glTF model folders (with links, pipes and paths that
//! lead out) added to a bank. Thousands of damaged inputs are fed to the same functions the
//! commands call, in-process, counting panics, hangs, partial outputs and files carried into a
//! bank from outside the model's folder. No GPU is needed.
//!
//! ```text
//! cargo run --release --example mutate_surfaces -- [--mutants N] [--seed S] [--only SURFACE]
//! ```
//!
//! `--mutants` is per surface (default 2000). A mutant slower than 2 s counts as a hang; one
//! slower than 60 s stops the run (a watchdog aborts the process naming it). The run prints a
//! table of outcomes per surface and exits 1 if anything failed.

use std::collections::BTreeMap;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use grove::aerial::{crowns, raster::RgbImage};
use grove::bank::import::{AddRequest, add};
use grove::lsystem::{derive, grammar::Grammar, mesh, presets::PRESETS, turtle};
use grove_systems::Sim;
use grove_systems::scene::Scene;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// The run's one seeded generator.
struct Rng(ChaCha8Rng);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0.random::<u64>()
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}

const HANG: Duration = Duration::from_secs(2);
const WATCHDOG: Duration = Duration::from_secs(60);

/// Numbers a hostile file would hold.
const HOSTILE: [&str; 18] = [
    "0",
    "-1",
    "1e-30",
    "1e30",
    "1e39",
    "-1e39",
    "NaN",
    "inf",
    "5e19",
    "2000",
    "4294967296",
    "18446744073709551615",
    "0.000001",
    "-0.0",
    "1e308",
    "65536",
    "3",
    "1e-9",
];

/// What happened to one mutant, and the failures of the run.
#[derive(Default)]
struct Tally {
    counts: BTreeMap<(String, String), u64>,
    failures: Vec<String>,
}

impl Tally {
    fn add(&mut self, surface: &str, outcome: &str) {
        *self.counts.entry((surface.to_string(), outcome.to_string())).or_default() += 1;
    }
}

/// The mutant being run, for the watchdog.
type Current = Arc<Mutex<Option<(String, Instant)>>>;

/// Runs one mutant: `Ok(outcome)` or `Err(failure)` from `f`, a panic, or a hang all counted.
fn run_one(
    tally: &mut Tally,
    current: &Current,
    surface: &str,
    label: String,
    f: impl FnOnce() -> Result<&'static str, String>,
) {
    *current.lock().unwrap() = Some((label.clone(), Instant::now()));
    let start = Instant::now();
    let r = catch_unwind(AssertUnwindSafe(f));
    let took = start.elapsed();
    *current.lock().unwrap() = None;
    match r {
        Ok(Ok(outcome)) => tally.add(surface, outcome),
        Ok(Err(failure)) => {
            tally.add(surface, "FAILED");
            tally.failures.push(format!("{surface} {label}: {failure}"));
        }
        Err(_) => {
            tally.add(surface, "PANICKED");
            tally.failures.push(format!("{surface} {label}: panicked"));
        }
    }
    if took > HANG {
        tally.add(surface, "HANG");
        tally.failures.push(format!("{surface} {label}: took {took:?}"));
    }
}

/// One text mutation: a number replaced by a hostile value, a line deleted, repeated many
/// times, or swapped with its neighbour, or the text cut short.
fn mutate_text(text: &str, rng: &mut Rng) -> (String, String) {
    let lines: Vec<&str> = text.lines().collect();
    match rng.below(6) {
        0 | 1 => {
            let spans = number_spans(text);
            if spans.is_empty() {
                return (text.to_string(), "unchanged".into());
            }
            let (a, b) = spans[rng.below(spans.len())];
            let v = HOSTILE[rng.below(HOSTILE.len())];
            (format!("{}{v}{}", &text[..a], &text[b..]), format!("number at {a} -> {v}"))
        }
        2 => {
            let i = rng.below(lines.len());
            let mut l = lines.clone();
            l.remove(i);
            (l.join("\n"), format!("line {i} deleted"))
        }
        3 => {
            let i = rng.below(lines.len());
            let times = [2, 20, 600][rng.below(3)];
            let mut l: Vec<&str> = lines[..i].to_vec();
            l.extend(std::iter::repeat_n(lines[i], times));
            l.extend(&lines[i + 1..]);
            (l.join("\n"), format!("line {i} x{times}"))
        }
        4 if lines.len() > 1 => {
            let i = rng.below(lines.len() - 1);
            let mut l = lines.clone();
            l.swap(i, i + 1);
            (l.join("\n"), format!("lines {i}, {} swapped", i + 1))
        }
        _ => {
            let mut cut = rng.below(text.len());
            while !text.is_char_boundary(cut) {
                cut -= 1;
            }
            (text[..cut].to_string(), format!("cut at {cut}"))
        }
    }
}

/// The byte ranges of the numbers in a text.
fn number_spans(text: &str) -> Vec<(usize, usize)> {
    let b = text.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < b.len() {
        if b[i].is_ascii_digit() && (i == 0 || !(b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'_')) {
            let start = if i > 0 && b[i - 1] == b'-' { i - 1 } else { i };
            let mut j = i;
            while j < b.len()
                && (b[j].is_ascii_digit()
                    || matches!(b[j], b'.' | b'e' | b'E')
                    || (matches!(b[j], b'-' | b'+') && matches!(b[j - 1], b'e' | b'E')))
            {
                j += 1;
            }
            out.push((start, j));
            i = j;
        } else {
            i += 1;
        }
    }
    out
}

/// Every file below `dir`, with its length, sorted.
fn listing(dir: &Path) -> Vec<(PathBuf, u64)> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        let Ok(entries) = std::fs::read_dir(&d) else { continue };
        for e in entries.flatten() {
            let p = e.path();
            let meta = std::fs::symlink_metadata(&p).unwrap();
            if meta.is_dir() {
                stack.push(p.clone());
            }
            out.push((p, meta.len()));
        }
    }
    out.sort();
    out
}

fn scenes(root: &Path, n: usize, rng: &mut Rng, tally: &mut Tally, current: &Current) {
    let seeds: Vec<(String, String)> = ["park", "garden", "pond", "forest"]
        .iter()
        .map(|s| (s.to_string(), std::fs::read_to_string(root.join(format!("assets/scenes/{s}.ron"))).unwrap()))
        .collect();
    for k in 0..n {
        let (name, seed) = &seeds[k % seeds.len()];
        let (text, how) = mutate_text(seed, rng);
        run_one(tally, current, "scene sections", format!("{name} #{k} ({how})"), || {
            let Ok(mut scene) = Scene::parse(&text, "mutant") else { return Ok("refused") };
            scene.dir = Some(root.join("assets/scenes"));
            match Sim::from_scene(&scene, scene.seed) {
                Err(_) => Ok("refused"),
                Ok(mut sim) => {
                    sim.run(2);
                    Ok("ran")
                }
            }
        });
    }
}

fn grammars(dir: &Path, n: usize, rng: &mut Rng, tally: &mut Tally, current: &Current) {
    let mut seeds: Vec<String> = PRESETS.iter().map(|(_, t)| t.to_string()).collect();
    seeds.push("name: param\naxiom: F(1)A(3)\nrule: F(l) -> F(l*0.8)[+F(l*0.6)]\nrule: A(x) : x > 1 -> F(x)[+A(x/2)]A(x-1)\nn: 5\n".into());
    for k in 0..n {
        let (text, how) = mutate_text(&seeds[k % seeds.len()], rng);
        let out = dir.join(format!("g{k}"));
        let write = k % 10 == 0;
        run_one(tally, current, "grammars", format!("#{k} ({how})"), || {
            let Ok(g) = Grammar::parse_file(&text, "mutant") else { return Ok("refused") };
            let limits = derive::Limits { max_symbols: 400_000, max_bytes: 4 << 20 };
            let mut s = derive::axiom(&g);
            for step in 1..=g.n.min(7) {
                match derive::step(&g, &s, step, 1, &limits) {
                    Ok(next) => s = next,
                    Err(_) => return Ok("refused"),
                }
            }
            let Ok(segs) = turtle::interpret_parallel(&s, &g, limits.max_bytes) else { return Ok("refused") };
            let opts = mesh::ModelOptions { height: g.height, ..Default::default() };
            let Ok(model) = mesh::build(&g, &segs, &opts) else { return Ok("refused") };
            // A valid model of over 30,000 segments takes seconds to write in a debug build: that
            // is work, not a hang, so only smaller ones are written here.
            if !write || segs.len() > 30_000 {
                return Ok("built");
            }
            match mesh::write(&out, "m", &g, &model) {
                Ok(_) => Ok("written"),
                Err(_)
                    if listing(&out).is_empty()
                        && listing(dir).iter().all(|(p, _)| !p.to_string_lossy().contains(".m-model")) =>
                {
                    Ok("refused when written")
                }
                Err(e) => Err(format!("a failed write left files: {e:#}")),
            }
        });
    }
}

/// A small RGB image as PNG and TIFF bytes.
fn image_seeds() -> Vec<(&'static str, Vec<u8>)> {
    let img = image::RgbImage::from_fn(24, 16, |x, y| image::Rgb([(x * 10) as u8, (y * 15) as u8, 90]));
    let mut out = Vec::new();
    for (ext, fmt) in [("png", image::ImageFormat::Png), ("tif", image::ImageFormat::Tiff)] {
        let mut bytes = std::io::Cursor::new(Vec::new());
        img.write_to(&mut bytes, fmt).unwrap();
        out.push((ext, bytes.into_inner()));
    }
    out
}

fn images_and_crowns(dir: &Path, n: usize, rng: &mut Rng, tally: &mut Tally, current: &Current) {
    let seeds = image_seeds();
    for k in 0..n {
        let (ext, seed) = &seeds[k % seeds.len()];
        let mut bytes = seed.clone();
        let how = match rng.below(4) {
            0 => {
                let i = rng.below(bytes.len());
                bytes[i] ^= 1 << rng.below(8);
                format!("bit flipped at {i}")
            }
            1 => {
                // The header's width and height (PNG: bytes 16..24) set to hostile values.
                let at = 16 + 4 * rng.below(2);
                let v = [0u32, 1, 65_535, 1 << 20, u32::MAX][rng.below(5)];
                if bytes.len() > at + 4 {
                    bytes[at..at + 4].copy_from_slice(&v.to_be_bytes());
                }
                format!("header field at {at} -> {v}")
            }
            2 => {
                let cut = rng.below(bytes.len());
                bytes.truncate(cut);
                format!("cut at {cut}")
            }
            _ => {
                let i = rng.below(bytes.len());
                let len = rng.below(64).min(bytes.len() - i);
                bytes[i..i + len].fill(0xff);
                format!("{len} bytes of 0xff at {i}")
            }
        };
        let path = dir.join(format!("i{k}.{ext}"));
        std::fs::write(&path, &bytes).unwrap();
        run_one(tally, current, "images", format!("#{k} {ext} ({how})"), || match RgbImage::load(&path, "image") {
            Ok(img) if img.data.len() == (img.width * img.height * 3) as usize => Ok("read"),
            Ok(_) => Err("an image whose data does not match its size".into()),
            Err(e) if e.to_string().contains('\n') => Err(format!("a two-line error: {e}")),
            Err(_) => Ok("refused"),
        });
    }
    let mut csv = String::from("id,x_px,y_px,area_px,radius_px,x_m,y_m,area_m2,radius_m\n");
    for i in 0..20u32 {
        csv.push_str(&format!(
            "{},{}.5,{}.5,{},3.1,{}.05,{}.05,{},0.31\n",
            i + 1,
            10 + i * 7,
            12 + i * 5,
            30 + i,
            1 + i,
            2 + i,
            0.3 + i as f32 * 0.01
        ));
    }
    for k in 0..n {
        let (text, how) = mutate_text(&csv, rng);
        let path = dir.join(format!("c{k}.csv"));
        std::fs::write(&path, &text).unwrap();
        run_one(tally, current, "crowns", format!("#{k} ({how})"), || {
            let a = crowns::read_csv(&path);
            let b = grove_systems::aerial::read_crowns(&path);
            if let Ok(rows) = &a
                && rows.iter().any(|c| ![c.x_m, c.y_m, c.radius_m, c.area_m2].iter().all(|v| v.is_finite()))
            {
                return Err("a non-finite crown was read".into());
            }
            Ok(if a.is_ok() && b.is_ok() { "read" } else { "refused" })
        });
    }
}

/// A glTF triangle with a texture, its buffer and image beside it, and hostile neighbours: a
/// secret file outside the folder, a link to it, a linked folder, a pipe.
fn model_folder(dir: &Path) -> (PathBuf, String) {
    let model = dir.join("model");
    std::fs::create_dir_all(model.join("tex")).unwrap();
    let mut bin: Vec<u8> = Vec::new();
    for v in [[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 2.0, 0.0]] {
        for c in v {
            bin.extend(c.to_le_bytes());
        }
    }
    for uv in [[0.0f32, 1.0], [1.0, 1.0], [0.0, 0.0]] {
        for c in uv {
            bin.extend(c.to_le_bytes());
        }
    }
    std::fs::write(model.join("tri.bin"), &bin).unwrap();
    let img = image::RgbaImage::from_pixel(4, 4, image::Rgba([40, 160, 60, 255]));
    img.save(model.join("tex/leaf.png")).unwrap();
    std::fs::write(dir.join("secret.bin"), b"SECRET-OUTSIDE-THE-MODEL-FOLDER").unwrap();
    std::os::unix::fs::symlink(dir.join("secret.bin"), model.join("link.bin")).unwrap();
    std::fs::create_dir_all(dir.join("elsewhere")).unwrap();
    img.save(dir.join("elsewhere/leaf.png")).unwrap();
    std::os::unix::fs::symlink(dir.join("elsewhere"), model.join("linkdir")).unwrap();
    let _ = std::process::Command::new("mkfifo").arg(model.join("pipe.bin")).status();
    let json = format!(
        r#"{{
  "asset": {{ "version": "2.0" }},
  "scene": 0,
  "scenes": [ {{ "nodes": [ 0 ] }} ],
  "nodes": [ {{ "mesh": 0 }} ],
  "meshes": [ {{ "primitives": [ {{ "attributes": {{ "POSITION": 0, "TEXCOORD_0": 1 }}, "material": 0 }} ] }} ],
  "materials": [ {{ "pbrMetallicRoughness": {{ "baseColorTexture": {{ "index": 0 }} }}, "alphaMode": "MASK", "alphaCutoff": 0.5 }} ],
  "textures": [ {{ "source": 0 }} ],
  "images": [ {{ "uri": "tex/leaf.png" }} ],
  "buffers": [ {{ "uri": "tri.bin", "byteLength": {} }} ],
  "bufferViews": [ {{ "buffer": 0, "byteOffset": 0, "byteLength": 36 }}, {{ "buffer": 0, "byteOffset": 36, "byteLength": 24 }} ],
  "accessors": [
    {{ "bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 2, 0] }},
    {{ "bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC2" }}
  ]
}}"#,
        bin.len()
    );
    (model, json)
}

/// URIs a hostile model names.
const URIS: [&str; 9] = [
    "../secret.bin",
    "/etc/passwd",
    "/dev/zero",
    "link.bin",
    "linkdir/leaf.png",
    "pipe.bin",
    "missing.bin",
    "tex/../../secret.bin",
    "data:application/octet-stream;base64,AAAA",
];

fn gltf_folders(dir: &Path, n: usize, rng: &mut Rng, tally: &mut Tally, current: &Current) {
    let (model, json) = model_folder(dir);
    let bank = dir.join("bank");
    std::fs::create_dir_all(&bank).unwrap();
    for k in 0..n {
        let (text, how) = match rng.below(3) {
            0 => {
                let target = ["\"tri.bin\"", "\"tex/leaf.png\""][rng.below(2)];
                let uri = URIS[rng.below(URIS.len())];
                (json.replacen(target, &format!("\"{uri}\""), 1), format!("{target} -> {uri}"))
            }
            _ => mutate_text(&json, rng),
        };
        let file = model.join(format!("m{k}.gltf"));
        std::fs::write(&file, &text).unwrap();
        let before = listing(&bank);
        run_one(tally, current, "glTF folders", format!("#{k} ({how})"), || {
            let req = AddRequest {
                file: file.clone(),
                bank: bank.clone(),
                name: Some(format!("m{k}")),
                species: None,
                kind: None,
                far: None,
            };
            match add(&req) {
                Ok(_) => Ok("added"),
                Err(e) if format!("{e:#}").contains('\n') => Err(format!("a two-line error: {e:#}")),
                Err(_) if listing(&bank) == before => Ok("refused"),
                Err(e) => Err(format!("refused ({e:#}) but the bank changed")),
            }
        });
        let _ = std::fs::remove_file(&file);
    }
    // Nothing from outside the model's folder reached the bank.
    for (p, _) in listing(&bank) {
        let meta = std::fs::symlink_metadata(&p).unwrap();
        if meta.file_type().is_symlink() {
            tally.failures.push(format!("glTF folders: the bank holds a link: {}", p.display()));
        } else if meta.is_file() && std::fs::read(&p).unwrap().windows(6).any(|w| w == b"SECRET") {
            tally.failures.push(format!("glTF folders: the bank holds the secret file: {}", p.display()));
        }
    }
}

fn main() {
    let mut n = 2000usize;
    let mut seed = 1u64;
    let mut only: Option<String> = None;
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mut i = 0;
    while i < args.len() {
        let value = args.get(i + 1).cloned().unwrap_or_default();
        match args[i].as_str() {
            "--mutants" => n = value.parse().expect("--mutants N"),
            "--seed" => seed = value.parse().expect("--seed S"),
            "--only" => only = Some(value),
            other => panic!("unknown argument {other}"),
        }
        i += 2;
    }
    std::panic::set_hook(Box::new(|_| {}));
    let current: Current = Arc::new(Mutex::new(None));
    let watch = current.clone();
    std::thread::spawn(move || {
        loop {
            std::thread::sleep(Duration::from_secs(1));
            if let Some((label, start)) = watch.lock().unwrap().clone()
                && start.elapsed() > WATCHDOG
            {
                eprintln!("mutant {label} has run for more than {WATCHDOG:?}: aborting the run");
                std::process::abort();
            }
        }
    });
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let work = tempfile::tempdir().unwrap();
    let mut rng = Rng(ChaCha8Rng::seed_from_u64(seed));
    let mut tally = Tally::default();
    let start = Instant::now();
    let want = |s: &str| only.as_deref().is_none_or(|o| o == s);
    if want("scenes") {
        scenes(&root, n, &mut rng, &mut tally, &current);
    }
    if want("grammars") {
        grammars(work.path(), n, &mut rng, &mut tally, &current);
    }
    if want("images") {
        images_and_crowns(work.path(), n, &mut rng, &mut tally, &current);
    }
    if want("gltf") {
        gltf_folders(work.path(), n, &mut rng, &mut tally, &current);
    }
    println!("| surface | outcome | mutants |\n|---|---|---|");
    for ((surface, outcome), c) in &tally.counts {
        println!("| {surface} | {outcome} | {c} |");
    }
    // SAFETY: an all-zero `rusage` is a valid value of this plain C struct.
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    // SAFETY: `usage` is valid for writes.
    unsafe { libc::getrusage(libc::RUSAGE_SELF, &mut usage) };
    println!(
        "{} mutants per surface, seed {seed}, {:.1} s, peak memory {} MB",
        n,
        start.elapsed().as_secs_f64(),
        usage.ru_maxrss / 1024
    );
    if !tally.failures.is_empty() {
        for f in tally.failures.iter().take(40) {
            println!("FAILED: {f}");
        }
        println!("{} failures", tally.failures.len());
        std::process::exit(1);
    }
    println!("no panic, hang, partial output or file from outside a model folder");
}
