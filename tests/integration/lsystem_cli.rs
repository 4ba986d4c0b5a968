//! `grove lsystem`: JSON output, bad grammars and limits (one line, exit 2), and generated models
//! that load, carry the wind channels and pass the Khronos glTF validator.

use crate::common;

use common::{assert_one_line_error, grove, validate_gltf_dir};

#[test]
fn derive_prints_length_and_counts() {
    let out = grove(&[
        "lsystem",
        "derive",
        "--axiom",
        "X",
        "--rule",
        "X=F[+X]F[-X]+X",
        "--rule",
        "F=FF",
        "--angle",
        "20",
        "--n",
        "2",
        "--json",
        "--print",
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    // By hand: X -> F[+X]F[-X]+X (12 symbols), then each F doubles and each X expands again.
    let want = "FF[+F[+X]F[-X]+X]FF[-F[+X]F[-X]+X]+F[+X]F[-X]+X";
    assert_eq!(v["string"], want);
    assert_eq!(v["length"], want.len());
    assert_eq!(v["counts"]["F"], want.matches('F').count());
    assert_eq!(v["counts"]["X"], 9);
    assert_eq!(v["counts"]["["], 8);
}

#[test]
fn bad_grammars_give_one_line_and_exit_2() {
    let dir = tempfile::tempdir().unwrap();
    let cases: &[(&str, &str)] = &[
        ("axiom: F\nrule: F -> F%F\n", "neither a letter nor a turtle command"),
        ("axiom: F\nrule: F -> F[+F\n", "without a matching ']'"),
        ("axiom: F]\n", "']' without a matching '['"),
        ("axiom: F\nrule: F -(0)-> FF\nrule: F -(0)-> F\n", "sum to a positive number"),
        ("axiom: F\nrule: F -(0)-> FF\n", "sum to a positive number"),
        ("axiom: F\nrule: F -(-1)-> FF\n", "weight"),
        ("axiom: F(1)\nrule: F(l) -> F(l*)\n", "expression"),
        ("axiom: F(1)\nrule: F(l) -> F(q)\n", "unknown name 'q'"),
        ("axiom: F(1)\nrule: F -> F\n", "parameters"),
        ("axiom: F\nangle: wide\n", "not a number"),
        ("axiom: F\ncolour: red\n", "unknown key"),
        ("rule: F -> FF\n", "no 'axiom:' line"),
    ];
    for (i, (text, needle)) in cases.iter().enumerate() {
        let p = dir.path().join(format!("bad{i}.lsys"));
        std::fs::write(&p, text).unwrap();
        let out = grove(&["lsystem", "derive", "--grammar", p.to_str().unwrap(), "--n", "2"]);
        assert_one_line_error(&out, 2, needle);
    }
    let out = grove(&["lsystem", "derive", "--axiom", "F", "--rule", "F=F?", "--n", "1"]);
    assert_one_line_error(&out, 2, "'?' at column 2");
    let out = grove(&["lsystem", "derive", "--preset", "oak"]);
    assert_one_line_error(&out, 2, "unknown preset 'oak'");
}

#[test]
fn a_derivation_past_the_limit_stops_with_one_line() {
    // bush 2 at n = 9 would have 1 + 19 (8^9 - 1) / 7 symbols.
    let out = grove(&["lsystem", "derive", "--preset", "bush2", "--n", "9", "--max-symbols", "100000000"]);
    let want = format!("{} symbols, more than the limit of 100000000", 1 + 19 * (8u64.pow(9) - 1) / 7);
    assert_one_line_error(&out, 2, &want);
    let out = grove(&["lsystem", "derive", "--preset", "bush2", "--n", "9", "--max-bytes", "1000"]);
    assert_one_line_error(&out, 2, "limit of 1000");
}

#[test]
fn models_load_carry_wind_channels_and_pass_the_validator() {
    let dir = tempfile::tempdir().unwrap();
    for (preset, n) in
        [("broadleaf", "6"), ("conifer", "12"), ("birch", "9"), ("shrub", "6"), ("bush2", "3"), ("abop-d", "5")]
    {
        let out = grove(&[
            "lsystem",
            "model",
            "--preset",
            preset,
            "--n",
            n,
            "--seed",
            "5",
            "--height",
            "5",
            "--out",
            dir.path().to_str().unwrap(),
        ]);
        assert!(out.status.success(), "{preset}: {}", String::from_utf8_lossy(&out.stderr));
        let path = dir.path().join(format!("{preset}.gltf"));
        let (doc, buffers, _) = gltf::import(&path).unwrap_or_else(|e| panic!("{preset}: {e}"));
        let mut top = f32::MIN;
        let mut low = f32::MAX;
        let mut masked = 0;
        for mat in doc.materials() {
            if mat.alpha_mode() == gltf::material::AlphaMode::Mask {
                masked += 1;
            }
        }
        assert_eq!(masked, 1, "{preset}: one alpha-clipped leaf material");
        for prim in doc.meshes().flat_map(|m| m.primitives().collect::<Vec<_>>()) {
            let wind = prim.attributes().find(|(s, _)| matches!(s, gltf::Semantic::Extras(n) if n == "WIND"));
            assert!(wind.is_some(), "{preset}: _WIND attribute");
            let r = prim.reader(|b| Some(&buffers[b.index()]));
            for p in r.read_positions().unwrap() {
                top = top.max(p[1]);
                low = low.min(p[1]);
            }
        }
        assert!(top > 4.5 && top < 6.0, "{preset}: height {top}");
        assert!(low > -0.2, "{preset}: lowest point {low}");
    }
    // The same model again does not overwrite the first.
    let out = grove(&["lsystem", "model", "--preset", "shrub", "--n", "6", "--out", dir.path().to_str().unwrap()]);
    assert_one_line_error(&out, 2, "already exists");

    let text = validate_gltf_dir(dir.path());
    assert_eq!(text.matches(": 0 errors").count(), 6, "{text}");
}
