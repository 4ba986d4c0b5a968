//! WGSL composed by one mechanism. A shader names the shared pieces it uses on import lines,
//! `// #import lighting, wind` (a comment, so every file stays valid WGSL on its own);
//! [`compose`] writes each piece once, the pieces a piece imports before it, then the shader.
//!
//! The pieces are the shared WGSL files of [`LIBRARY`], pieces written from Rust that any shader
//! may import (the haze's constants, `haze::SHADER_CONSTANTS`; the wind's uniform,
//! `WindParams::WGSL`), and pieces the caller generates from Rust (the grass's constants,
//! `grass::data::shader_constants`; the trees' `Material`), so a constant or a struct shared by
//! Rust and WGSL is written in Rust only (structs with `grove_systems::wgsl_struct!`). It names no
//! feature module, only the leaf `haze`.

use grove_systems::wind_model::WindParams;

/// The shared WGSL files by import name.
pub(crate) const LIBRARY: &[(&str, &str)] = &[
    // The frame uniforms, the lighting resources and the shading model of every lit pass.
    ("lighting", include_str!("lighting.wgsl")),
    // sRGB decoding for textures sampled through a linear format.
    ("srgb", include_str!("srgb.wgsl")),
    // The per-vertex wind models (CPU twins in grove-systems' `wind_model`).
    ("wind", include_str!("trees/wind.wgsl")),
    // The impostors' hemi-octahedral view layout (CPU twins in `trees::impostor`).
    ("octa", include_str!("trees/impostor/octa.wgsl")),
    // Sampling a clipmap of an aerial photograph.
    ("clipmap", include_str!("clipmap/clipmap.wgsl")),
    // What the grass cull pass writes per blade and the blade draw's uniforms.
    ("grass_shapes", include_str!("grass/shapes.wgsl")),
];

/// The pieces written from Rust that any shader may import: the haze's constants
/// ([`super::haze`]) and the wind's uniform, declared once in grove-systems
/// ([`WindParams`], `grove_systems::wgsl_struct!`).
fn built_in() -> [(&'static str, &'static str); 2] {
    [("haze", super::haze::SHADER_CONSTANTS.as_str()), ("wind_params", WindParams::WGSL)]
}

/// The names a WGSL text imports, in order: every `// #import a, b` line.
pub(crate) fn imports(src: &str) -> Vec<&str> {
    src.lines()
        .filter_map(|l| l.trim().strip_prefix("// #import "))
        .flat_map(|names| names.split(',').map(str::trim).filter(|n| !n.is_empty()))
        .collect()
}

/// `src` with the pieces it imports written before it, each once (a piece's own imports before
/// it), from [`LIBRARY`] and then `generated` (name, WGSL text). An import of no known piece
/// is a mistake in the program's own shaders: it panics with the name, and the tests compose
/// every shader.
pub(crate) fn compose(src: &str, generated: &[(&str, &str)]) -> String {
    let mut out = String::new();
    let mut done: Vec<&str> = Vec::new();
    for name in imports(src) {
        add(name, generated, &mut done, &mut out, &mut Vec::new());
    }
    out.push_str(src);
    out
}

/// Writes piece `name` and, before it, what it imports, unless written already; `path` holds
/// the pieces being written, to name an import circle.
fn add<'a>(
    name: &'a str,
    generated: &[(&'a str, &'a str)],
    done: &mut Vec<&'a str>,
    out: &mut String,
    path: &mut Vec<&'a str>,
) {
    if done.contains(&name) {
        return;
    }
    assert!(!path.contains(&name), "WGSL import circle: {} -> {name}", path.join(" -> "));
    let text = LIBRARY.iter().chain(generated).chain(&built_in()).find(|(n, _)| *n == name).map(|(_, t)| *t);
    let text = text.unwrap_or_else(|| panic!("WGSL import of an unknown piece '{name}'"));
    path.push(name);
    for dep in imports(text) {
        add(dep, generated, done, out, path);
    }
    path.pop();
    done.push(name);
    out.push_str(text);
    out.push('\n');
}

/// The members (name, byte offset) and the size that WGSL gives the struct `name` declared in
/// `wgsl`, as naga lays it out; `None` when the text does not parse or declares no such struct.
/// For the tests that hold a struct declared in Rust to the offsets its shaders read.
#[cfg(test)]
pub(crate) fn struct_layout(wgsl: &str, name: &str) -> Option<(Vec<(String, usize)>, usize)> {
    let module = wgpu::naga::front::wgsl::parse_str(wgsl).ok()?;
    module.types.iter().find_map(|(_, ty)| match &ty.inner {
        wgpu::naga::TypeInner::Struct { members, span } if ty.name.as_deref() == Some(name) => Some((
            members.iter().map(|m| (m.name.clone().unwrap_or_default(), m.offset as usize)).collect(),
            *span as usize,
        )),
        _ => None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pieces_come_once_before_what_imports_them() {
        let generated = [("a", "// #import b\nconst A: u32 = B;"), ("b", "const B: u32 = 1u;")];
        let out = compose("// #import a, b\n// #import a\nfn f() -> u32 { return A; }", &generated);
        assert_eq!(out.matches("const B").count(), 1, "{out}");
        assert_eq!(out.matches("const A").count(), 1, "{out}");
        let (a, b, f) = (out.find("const A").unwrap(), out.find("const B").unwrap(), out.find("fn f").unwrap());
        assert!(b < a && a < f, "{out}");
    }

    #[test]
    #[should_panic(expected = "unknown piece 'nope'")]
    fn an_unknown_import_is_named() {
        compose("// #import nope\n", &[]);
    }

    #[test]
    #[should_panic(expected = "import circle")]
    fn an_import_circle_is_named() {
        compose("// #import a\n", &[("a", "// #import b\n"), ("b", "// #import a\n")]);
    }

    /// Every shader file under src/render imports only known pieces (the render tests compile
    /// every composed shader on the device).
    #[test]
    fn every_shader_file_imports_known_pieces() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("src/render");
        let mut files = Vec::new();
        let mut stack = vec![root];
        while let Some(dir) = stack.pop() {
            for e in std::fs::read_dir(dir).unwrap().flatten() {
                let p = e.path();
                if p.is_dir() {
                    stack.push(p);
                } else if p.extension().is_some_and(|x| x == "wgsl") {
                    files.push(p);
                }
            }
        }
        assert!(files.len() >= 15, "{files:?}");
        let known: Vec<&str> =
            LIBRARY.iter().chain(&built_in()).map(|(n, _)| *n).chain(["grass_constants", "material"]).collect();
        for f in &files {
            let text = std::fs::read_to_string(f).unwrap();
            for name in imports(&text) {
                assert!(known.contains(&name), "{}: imports unknown '{name}'", f.display());
            }
        }
    }

    #[test]
    fn lighting_reads_the_haze_constants_written_in_rust() {
        let wgsl = compose("// #import lighting\n", &[]);
        for line in super::super::haze::SHADER_CONSTANTS.lines() {
            assert_eq!(wgsl.matches(line).count(), 1, "{line}");
        }
        assert!(wgsl.contains("const HAZE_START: f32 = 40.0;"), "{}", *super::super::haze::SHADER_CONSTANTS);
    }

    #[test]
    fn the_wind_uniform_is_written_once_from_rust() {
        // The impostors read the wind through wind.wgsl, which imports the piece: one
        // declaration, the one grove-systems writes, laid out at the Rust struct's offsets.
        let wgsl = compose(include_str!("trees/impostor/impostor.wgsl"), &[]);
        assert_eq!(wgsl.matches("struct WindParams {").count(), 1, "{wgsl}");
        assert!(wgsl.contains(WindParams::WGSL));
        let (members, size) =
            struct_layout(&wgsl, "WindParams").expect("the composed shader parses and declares WindParams");
        let rust: Vec<(String, usize)> = WindParams::FIELDS.iter().map(|(n, o)| (n.to_string(), *o)).collect();
        assert_eq!(members, rust);
        assert_eq!(size, std::mem::size_of::<WindParams>());
        assert_eq!(size, WindParams::SIZE);
    }

    #[test]
    fn naga_lays_out_a_small_struct() {
        // naga's layout of a small struct: the vec2 aligned to 8 bytes, the size rounded up to
        // its alignment; a struct the text does not declare is none.
        let (members, size) = struct_layout("struct S { a: f32, b: vec2<f32>, }", "S").unwrap();
        assert_eq!(members, [("a".to_string(), 0), ("b".to_string(), 8)]);
        assert_eq!(size, 16);
        assert_eq!(struct_layout("struct S { a: f32, }", "T"), None);
    }
}
