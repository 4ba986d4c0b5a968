//! Water on the command line: `grove scene check` lists the pond; bad water fields in a scene
//! give one clear line on stderr and exit code 2, whichever command reads the scene.

use crate::common;

use common::{assert_one_line_error, grove, grove_with, root};

fn pond() -> String {
    std::fs::read_to_string(root().join("assets/scenes/pond.ron")).unwrap()
}

fn broken(name: &str, text: &str, needle: &str) {
    assert!(text != pond(), "{name}: the mutation must change the scene");
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join(format!("{name}.ron"));
    std::fs::write(&path, text).unwrap();
    for cmd in [&["scene", "check"][..], &["sim", "--ticks", "1", "--scene"][..]] {
        let out = grove_with(cmd, &path);
        assert_one_line_error(&out, 2, needle);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(stderr.contains(&format!("{name}.ron")), "names the file: {stderr}");
    }
}

#[test]
fn scene_check_lists_the_pond() {
    let out = grove(&["scene", "check", "assets/scenes/pond.ron"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("water 'pond': 48 vertices") && text.contains("surface at -0.15 m"), "{text}");
}

#[test]
fn bad_water_fields_give_one_line_errors() {
    broken("depth", &pond().replacen("depth: 1.35,", "depth: -2.0,", 1), "depth -2 must be in (0, 10000]");
    broken(
        "colour",
        &pond().replacen("colour: (0.02, 0.07, 0.06),", "colour: (0.02, 7.0, 0.06),", 1),
        "colour component 7",
    );
    broken("ripples", &pond().replacen("ripples: 1.0,", "ripples: 9.0,", 1), "ripples 9 is outside");
    broken("height", &pond().replacen("height: -0.15,", "height: NaN,", 1), "height");
    broken("unknown", &pond().replacen("ripples: 1.0,", "ripples: 1.0, waves: 2,", 1), "waves");
    broken("missing", &pond().replacen("depth: 1.35,", "", 1), "depth");
    let p = pond();
    let start = p.find("polygon: [").unwrap();
    let end = start + p[start..].find("],").unwrap() + 2;
    broken("two", &format!("{}polygon: [(0.0, 0.0), (1.0, 0.0)],{}", &p[..start], &p[end..]), "at least 3");
    broken(
        "bowtie",
        &format!("{}polygon: [(0.0, 0.0), (2.0, 2.0), (2.0, 0.0), (0.0, 2.0)],{}", &p[..start], &p[end..]),
        "cross",
    );
}

#[test]
fn render_draws_the_pond_unless_told_no_water() {
    let dir = tempfile::tempdir().unwrap();
    let (with, without) = (dir.path().join("with.png"), dir.path().join("without.png"));
    for (path, extra) in [(&with, None), (&without, Some("--no-water"))] {
        let p = path.display().to_string();
        let mut args =
            vec!["render", "--scene", "assets/scenes/pond.ron", "--out", p.as_str(), "--width", "96", "--height", "64"];
        args.extend(extra);
        let out = grove(&args);
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    }
    let (a, b) = (image::open(&with).unwrap().to_rgba8(), image::open(&without).unwrap().to_rgba8());
    // The pond lies in the middle of the scene's view, a little below the centre.
    let changed = (28..40u32).flat_map(|y| (30..66u32).map(move |x| (x, y))).filter(|&(x, y)| {
        let (p, q) = (a.get_pixel(x, y).0, b.get_pixel(x, y).0);
        (0..3).any(|c| p[c].abs_diff(q[c]) > 30)
    });
    assert!(changed.count() > 100, "--no-water left the pond's pixels as they were");
}
