//! `grove render` and `grove assets` from the command line: outputs and one-line errors.

use std::path::{Path, PathBuf};
use std::process::Command;

fn grove() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_grove"));
    c.current_dir(env!("CARGO_MANIFEST_DIR"));
    c
}

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Runs grove, expecting failure with exactly one line on stderr that contains `needle`.
fn fails_with(args: &[&str], needle: &str) {
    let out = grove().args(args).output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    let lines: Vec<&str> = err
        .lines()
        .filter(|l| !l.contains("XDG_RUNTIME_DIR") && !l.trim().is_empty())
        .collect();
    assert!(!out.status.success(), "{args:?} should fail");
    assert_eq!(
        lines.len(),
        1,
        "{args:?}: expected one error line, got {err}"
    );
    assert!(
        lines[0].starts_with("error: ") && lines[0].contains(needle),
        "{args:?}: {}",
        lines[0]
    );
    assert!(
        !err.contains("panicked") && !err.contains("internal error"),
        "{err}"
    );
}

fn copy_model(dir: &Path, name: &str) -> PathBuf {
    let src = root().join("assets/trees");
    std::fs::create_dir_all(dir.join("textures")).unwrap();
    for f in std::fs::read_dir(src.join("textures")).unwrap() {
        let f = f.unwrap().path();
        std::fs::copy(&f, dir.join("textures").join(f.file_name().unwrap())).unwrap();
    }
    std::fs::copy(
        src.join(format!("{name}.bin")),
        dir.join(format!("{name}.bin")),
    )
    .unwrap();
    std::fs::copy(
        src.join(format!("{name}.gltf")),
        dir.join(format!("{name}.gltf")),
    )
    .unwrap();
    dir.join(format!("{name}.gltf"))
}

#[test]
fn missing_scene_and_model_give_one_line_errors() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("x.png");
    let out = out.to_str().unwrap();
    fails_with(
        &["render", "--scene", "no/such/scene.ron", "--out", out],
        "no such file",
    );
    fails_with(
        &["render", "--model", "no/such/tree.gltf", "--out", out],
        "no such file",
    );
}

#[test]
fn broken_gltf_and_missing_texture_give_one_line_errors() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("x.png");
    let out = out.to_str().unwrap();
    let broken = tmp.path().join("broken.gltf");
    std::fs::write(
        &broken,
        "{ \"asset\": { \"version\": \"2.0\" }, \"meshes\": [ ",
    )
    .unwrap();
    fails_with(
        &["render", "--model", broken.to_str().unwrap(), "--out", out],
        "not a valid glTF",
    );

    let dir = tmp.path().join("m");
    let model = copy_model(&dir, "shrub-billboard");
    std::fs::remove_file(dir.join("textures/shrub-card.png")).unwrap();
    fails_with(
        &["render", "--model", model.to_str().unwrap(), "--out", out],
        "texture 'textures/shrub-card.png': no such file",
    );

    std::fs::write(dir.join("textures/shrub-card.png"), b"not a png").unwrap();
    fails_with(
        &["render", "--model", model.to_str().unwrap(), "--out", out],
        "cannot decode",
    );
}

#[test]
fn render_writes_a_png_of_the_requested_size_and_refuses_to_overwrite() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("study.png");
    let st = grove()
        .args([
            "render",
            "--scene",
            "assets/scenes/study.ron",
            "--out",
            out.to_str().unwrap(),
            "--width",
            "96",
            "--height",
            "64",
        ])
        .output()
        .unwrap();
    assert!(
        st.status.success(),
        "{}",
        String::from_utf8_lossy(&st.stderr)
    );
    let img = image::open(&out).unwrap();
    assert_eq!((img.width(), img.height()), (96, 64));
    fails_with(
        &[
            "render",
            "--scene",
            "assets/scenes/study.ron",
            "--out",
            out.to_str().unwrap(),
            "--width",
            "96",
            "--height",
            "64",
        ],
        "already exists",
    );
}

#[test]
fn frame_sequence_moves_the_sun() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("frames");
    let st = grove()
        .args([
            "render",
            "--scene",
            "assets/scenes/study.ron",
            "--frames",
            "3",
            "--fps",
            "1",
            "--time-rate",
            "7200",
            "--out",
            dir.to_str().unwrap(),
            "--width",
            "64",
            "--height",
            "48",
        ])
        .output()
        .unwrap();
    assert!(
        st.status.success(),
        "{}",
        String::from_utf8_lossy(&st.stderr)
    );
    let frames: Vec<_> = (0..3)
        .map(|i| {
            image::open(dir.join(format!("frame_{i:05}.png")))
                .unwrap()
                .to_rgba8()
        })
        .collect();
    // Two hours of sun per frame: consecutive frames differ.
    assert_ne!(frames[0].as_raw(), frames[1].as_raw());
    assert_ne!(frames[1].as_raw(), frames[2].as_raw());
}

#[test]
fn a_glb_model_without_tangents_or_textures_renders() {
    // A minimal third-party-style model: one triangle, positions only, embedded in a GLB.
    let positions: [f32; 9] = [-1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 2.0, 0.0];
    let bin: Vec<u8> = bytemuck::cast_slice(&positions).to_vec();
    let json = format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],"nodes":[{{"mesh":0,"translation":[0,0.5,0]}}],
        "meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}}}}]}}],
        "accessors":[{{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[-1,0,0],"max":[1,2,0]}}],
        "bufferViews":[{{"buffer":0,"byteLength":{}}}],"buffers":[{{"byteLength":{}}}]}}"#,
        bin.len(),
        bin.len()
    );
    let mut json = json.into_bytes();
    while json.len() % 4 != 0 {
        json.push(b' ');
    }
    let total = 12 + 8 + json.len() + 8 + bin.len();
    let mut glb = Vec::new();
    glb.extend_from_slice(b"glTF");
    glb.extend_from_slice(&2u32.to_le_bytes());
    glb.extend_from_slice(&(total as u32).to_le_bytes());
    glb.extend_from_slice(&(json.len() as u32).to_le_bytes());
    glb.extend_from_slice(b"JSON");
    glb.extend_from_slice(&json);
    glb.extend_from_slice(&(bin.len() as u32).to_le_bytes());
    glb.extend_from_slice(b"BIN\0");
    glb.extend_from_slice(&bin);
    let tmp = tempfile::tempdir().unwrap();
    let model = tmp.path().join("tri.glb");
    std::fs::write(&model, glb).unwrap();
    let out = tmp.path().join("tri.png");
    let st = grove()
        .args([
            "render",
            "--model",
            model.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--width",
            "64",
            "--height",
            "48",
        ])
        .output()
        .unwrap();
    assert!(
        st.status.success(),
        "{}",
        String::from_utf8_lossy(&st.stderr)
    );
    let img = image::open(&out).unwrap().to_rgba8();
    // The white triangle is framed in the middle of the image.
    let p = img.get_pixel(32, 24).0;
    assert!(p[0] > 100 && p[1] > 100 && p[2] > 100, "centre pixel {p:?}");
}

#[test]
fn a_replay_renders_at_a_tick_and_differs_from_its_start() {
    let tmp = tempfile::tempdir().unwrap();
    let rec = "replays/scenarios/plant-two.jsonl";
    let render = |tick: &str, name: &str| {
        let out = tmp.path().join(name);
        let st = grove()
            .args([
                "render",
                "--replay",
                rec,
                "--tick",
                tick,
                "--out",
                out.to_str().unwrap(),
                "--width",
                "96",
                "--height",
                "64",
            ])
            .output()
            .unwrap();
        assert!(
            st.status.success(),
            "{}",
            String::from_utf8_lossy(&st.stderr)
        );
        image::open(&out).unwrap().to_rgba8()
    };
    let start = render("0", "start.png");
    let later = render("150", "later.png");
    assert_eq!((later.width(), later.height()), (96, 64));
    // Two trees were planted in between, so the pictures differ.
    let changed = start
        .pixels()
        .zip(later.pixels())
        .filter(|(a, b)| a != b)
        .count();
    assert!(changed > 50, "only {changed} pixels changed");
    fails_with(
        &[
            "render",
            "--replay",
            rec,
            "--tick",
            "99999",
            "--out",
            tmp.path().join("x.png").to_str().unwrap(),
        ],
        "ends at tick",
    );
    fails_with(
        &[
            "render",
            "--replay",
            "replays/nope.jsonl",
            "--tick",
            "1",
            "--out",
            tmp.path().join("y.png").to_str().unwrap(),
        ],
        "no such file",
    );
}

/// `grove bench render-gpu` times real GPUs only: on a software adapter (lavapipe in CI) it
/// refuses with one line; on a GPU it reports the passes' timestamp-query times.
#[test]
fn gpu_benchmark_refuses_a_software_adapter() {
    let gpu = grove::render::offscreen::Gpu::new().unwrap();
    if gpu.is_cpu() {
        fails_with(
            &["bench", "render-gpu"],
            "needs a real GPU, but wgpu picked the software adapter",
        );
    } else {
        let out = grove().args(["bench", "render-gpu"]).output().unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        assert!(
            v["render_gpu"]["forest_10k_trees"]["mixed_shadows_on"]["gpu_main_pass_ms"]
                .as_f64()
                .unwrap()
                > 0.0
        );
    }
}

/// `--model FILE --background transparent`: the model alone, its alpha the coverage. grove's
/// renderer neither blends nor multisamples trees, so every pixel is covered or not (alpha 0 or
/// 255): 0 off the model (the corners), 255 on its trunk; and where the model is, the colour is
/// the one the same model has on its stage (the same light and shadows).
#[test]
fn a_transparent_model_render_is_the_model_alone_with_its_coverage() {
    let tmp = tempfile::tempdir().unwrap();
    let model = root().join("assets/trees/broadleaf-mesh.gltf");
    let render = |background: &str| {
        let out = tmp.path().join(format!("{background}.png"));
        let st = grove()
            .args(["render", "--model", model.to_str().unwrap(), "--background", background, "--width", "160", "--height", "120", "--out", out.to_str().unwrap()])
            .output()
            .unwrap();
        assert!(st.status.success(), "{}", String::from_utf8_lossy(&st.stderr));
        image::open(&out).unwrap().to_rgba8()
    };
    let (clear, stage) = (render("transparent"), render("sky"));
    for (x, y) in [(0, 0), (159, 0), (0, 119), (159, 119)] {
        assert_eq!(clear.get_pixel(x, y).0[3], 0, "corner ({x}, {y}) is off the model");
    }
    assert!(clear.pixels().all(|p| p.0[3] == 0 || p.0[3] == 255), "coverage is 0 or 255");
    // The trunk at 0.5 m up, where the stage's camera sees it.
    let data = grove::models::load_model(&model).unwrap();
    let (eye, target) = grove_systems::stage::frame_bounds(data.bounds.0, data.bounds.1, 40f32.to_radians(), 160.0 / 120.0);
    let rotation = grove_systems::components::Pose::looking_at(eye, target).rotation;
    let m = grove::render::camera_matrix(&grove::render::Camera { position: eye, rotation, fov_y: 40f32.to_radians() }, 160.0 / 120.0);
    let p = m.project_point3(glam::Vec3::new(0.0, 0.5, 0.0));
    let (px, py) = (((p.x + 1.0) * 80.0) as u32, ((1.0 - p.y) * 60.0) as u32);
    assert_eq!(clear.get_pixel(px, py).0[3], 255, "the trunk at ({px}, {py}) is covered");
    let covered = clear.pixels().filter(|p| p.0[3] == 255).count();
    assert!(covered > 160 * 120 / 50, "the model covers {covered} pixels (over 2 % of the frame)");
    for (a, b) in clear.pixels().zip(stage.pixels()) {
        if a.0[3] == 255 {
            assert_eq!(a.0[..3], b.0[..3], "a covered pixel is as the stage draws it");
        }
    }
    let out = tmp.path().join("x.png");
    let m = model.to_str().unwrap();
    fails_with(&["render", "--model", m, "--background", "blue", "--out", out.to_str().unwrap()], "blue");
    fails_with(&["render", "--scene", "assets/scenes/study.ron", "--background", "transparent", "--out", out.to_str().unwrap()], "--model");
}

/// `--model FILE --tick T`: the model in the study's wind after T ticks, which moves it.
#[test]
fn a_model_at_a_tick_sways_in_the_study_s_wind() {
    let tmp = tempfile::tempdir().unwrap();
    let model = root().join("assets/trees/birch-mesh.gltf");
    let render = |tick: Option<&str>, name: &str| {
        let out = tmp.path().join(format!("{name}.png"));
        let mut args = vec!["render", "--model", model.to_str().unwrap(), "--background", "transparent", "--width", "96", "--height", "72", "--out", out.to_str().unwrap()];
        if let Some(t) = tick {
            args.extend(["--tick", t]);
        }
        let st = grove().args(&args).output().unwrap();
        assert!(st.status.success(), "{}", String::from_utf8_lossy(&st.stderr));
        image::open(&out).unwrap().to_rgba8()
    };
    let (calm, a, b) = (render(None, "calm"), render(Some("60"), "a"), render(Some("90"), "b"));
    let differ = |x: &image::RgbaImage, y: &image::RgbaImage| x.pixels().zip(y.pixels()).filter(|(p, q)| p.0[3] != q.0[3]).count();
    assert!(differ(&calm, &a) > 0 && differ(&a, &b) > 0, "the wind moves the model's silhouette");
    let out = tmp.path().join("x.png");
    fails_with(&["render", "--model", model.to_str().unwrap(), "--tick", "999999999", "--out", out.to_str().unwrap()], "--tick");
    fails_with(&["render", "--scene", "assets/scenes/study.ron", "--tick", "3", "--out", out.to_str().unwrap()], "--tick");
}
