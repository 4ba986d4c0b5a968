//! The app's files import each other in one direction only: no import circles.
//!
//! One node per file under `src/` (the library and the binary together: their module names do
//! not overlap), an edge for every `crate::…` and `super::…` path in its code, resolved to the
//! longest module path that is a file; and one node per folder, a folder importing another when one
//! of its files imports one of the other's (a folder and its own subfolders do not count against
//! each other). The graphs of grove-systems are checked by `systems/tests/import_graph.rs` with
//! the same functions.

use crate::graph;

use std::path::Path;

use graph::{crate_with_folder_cycle, file_graph, find_cycle, folder_graph, folder_of, module_path, nested};

#[test]
fn file_paths_and_relative_imports_resolve_to_files() {
    let src = Path::new("src");
    assert_eq!(module_path(src, Path::new("src/render/frame.rs")), "render::frame");
    assert_eq!(module_path(src, Path::new("src/render/mod.rs")), "render");
    assert_eq!(module_path(src, Path::new("src/lib.rs")), "");
    // A made-up crate with a circle through `super::` and one through `crate::` paths.
    let dir = std::env::temp_dir().join(format!("grove-import-graph-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(dir.join("a")).unwrap();
    std::fs::write(dir.join("lib.rs"), "pub mod a;\npub mod b;\n").unwrap();
    std::fs::write(dir.join("a/mod.rs"), "pub mod x;\npub mod y;\n").unwrap();
    std::fs::write(dir.join("a/x.rs"), "use super::y::Y;\n// crate::b is only a comment\n").unwrap();
    std::fs::write(dir.join("a/y.rs"), "pub struct Y;\n").unwrap();
    std::fs::write(dir.join("b.rs"), "use crate::a::x;\n").unwrap();
    let edges = file_graph(&dir);
    assert_eq!(edges["a::x"].iter().collect::<Vec<_>>(), ["a::y"]);
    assert_eq!(edges["b"].iter().collect::<Vec<_>>(), ["a::x"]);
    assert_eq!(find_cycle(&edges), None);
    std::fs::write(dir.join("a/y.rs"), "pub struct Y(crate::b::B);\n").unwrap();
    let cycle = find_cycle(&file_graph(&dir)).expect("a circle through a::y, b and a::x");
    assert!(cycle.contains(&"a::y".to_string()) && cycle.contains(&"b".to_string()), "{cycle:?}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn the_app_has_no_import_circles() {
    let edges = file_graph(Path::new(env!("CARGO_MANIFEST_DIR")).join("src").as_path());
    assert!(edges.get("html::page").is_some_and(|t| t.contains("study::report")), "the graph was read");
    if let Some(cycle) = find_cycle(&edges) {
        panic!("import circle: {}", cycle.join(" -> "));
    }
}

#[test]
fn render_features_import_nothing_from_the_renderer_above_them() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let edges = file_graph(src.as_path());
    // A feature is a folder of src/render; the renderer is render/mod.rs and the frame.
    let features: Vec<String> = std::fs::read_dir(src.join("render"))
        .unwrap()
        .filter_map(|e| e.ok())
        .filter(|e| e.path().is_dir())
        .map(|e| format!("render::{}", e.file_name().to_string_lossy()))
        .collect();
    assert!(features.iter().any(|f| f == "render::trees") && features.len() >= 8, "{features:?}");
    let mut upward = Vec::new();
    for (from, to) in &edges {
        if !features.iter().any(|f| from == f || from.starts_with(&format!("{f}::"))) {
            continue;
        }
        for t in to.iter().filter(|t| *t == "render" || *t == "render::frame") {
            upward.push(format!("{from} -> {t}"));
        }
    }
    assert!(upward.is_empty(), "features import from the renderer above them: {upward:?}");
    // The check sees such an import: the renderer's own frame imports the renderer.
    assert!(edges["render::frame"].contains("render"), "the graph was read");
}

#[test]
fn folders_are_read_from_files() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    assert_eq!(folder_of(&src, "render::canopy"), "render::canopy", "a folder's mod.rs is the folder");
    assert_eq!(folder_of(&src, "render::canopy::extents"), "render::canopy");
    assert_eq!(folder_of(&src, "render::frame"), "render");
    assert_eq!(folder_of(&src, "atomic_write"), "");
    assert!(nested("render", "render::canopy") && nested("", "aerial") && !nested("render::canopy", "render::clipmap"));
    let dir = crate_with_folder_cycle("app");
    assert_eq!(find_cycle(&file_graph(&dir)), None, "the files import each other in one direction");
    let cycle = find_cycle(&folder_graph(&dir)).expect("a circle between folders a and b");
    assert!(cycle.contains(&"a".to_string()) && cycle.contains(&"b".to_string()), "{cycle:?}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn the_app_has_no_circles_between_folders() {
    let edges = folder_graph(Path::new(env!("CARGO_MANIFEST_DIR")).join("src").as_path());
    assert!(edges.get("render::clipmap").is_some_and(|t| t.contains("aerial")), "the folder graph was read: {edges:?}");
    if let Some(cycle) = find_cycle(&edges) {
        panic!("import circle between folders: {}", cycle.join(" -> "));
    }
}

#[test]
fn models_are_loaded_without_the_renderer() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let edges = folder_graph(&src);
    assert!(
        edges.get("bank").is_some_and(|t| t.contains("models"))
            && edges.get("render").is_some_and(|t| t.contains("models")),
        "the folder graph was read: {edges:?}"
    );
    // What `models` imports from the app: itself and the files at the top of the crate only.
    let mut above = Vec::new();
    for (from, to) in file_graph(&src).iter().filter(|(from, _)| folder_of(&src, from) == "models") {
        for t in to.iter().filter(|t| !folder_of(&src, t).is_empty() && folder_of(&src, t) != "models") {
            above.push(format!("{from} -> {t}"));
        }
    }
    assert!(above.is_empty(), "models import the app's folders: {above:?}");
    for entry in std::fs::read_dir(src.join("models")).unwrap() {
        let path = entry.unwrap().path();
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(!text.contains("wgpu"), "{} names wgpu", path.display());
    }
}
