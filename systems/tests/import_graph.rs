//! The crate's modules import each other in one direction only: no import circles.
//!
//! Every `crate::NAME` in the code (not in comments) of a file under `systems/src` is an edge
//! from the file's top-level module to the module `NAME` (a folder such as `systems/` or
//! `wind_model/` is one module). The graph must have no cycle; nor must the graph of folders,
//! where a folder imports another when one of its files imports one of the other's.

mod graph;

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

use graph::{crate_with_folder_cycle, file_graph, find_cycle, folder_graph, graph, references};

#[test]
fn the_checker_finds_a_circle() {
    let mut edges: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    edges.entry("a".into()).or_default().insert("b".into());
    edges.entry("b".into()).or_default().insert("c".into());
    edges.entry("c".into()).or_default().insert("a".into());
    assert_eq!(find_cycle(&edges).unwrap(), ["a", "b", "c", "a"]);
    edges.get_mut("c").unwrap().clear();
    assert_eq!(find_cycle(&edges), None);
    // Comments do not count; code does.
    let refs = references("use crate::mode::Mode; // crate::sim\n/// [`crate::hash`]\nlet x = crate::wind_model::TAU;");
    assert_eq!(refs.into_iter().collect::<Vec<_>>(), ["mode", "wind_model"]);
}

#[test]
fn systems_has_no_import_circles() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let edges = graph(&src);
    assert!(edges.contains_key("sim") && edges["sim"].contains("schedule"), "the graph was read: {edges:?}");
    if let Some(cycle) = find_cycle(&edges) {
        panic!("import circle: {}", cycle.join(" -> "));
    }
}

#[test]
fn the_folder_check_finds_a_circle_the_file_check_does_not() {
    let dir = crate_with_folder_cycle("systems");
    assert_eq!(find_cycle(&file_graph(&dir)), None, "the files import each other in one direction");
    let cycle = find_cycle(&folder_graph(&dir)).expect("a circle between folders a and b");
    assert_eq!(cycle.len(), 3, "{cycle:?}");
    assert!(cycle.contains(&"a".to_string()) && cycle.contains(&"b".to_string()), "{cycle:?}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn systems_has_no_circles_between_folders() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let edges = folder_graph(&src);
    assert!(edges.get("scenario").is_some_and(|t| t.contains("replay")), "the folder graph was read: {edges:?}");
    if let Some(cycle) = find_cycle(&edges) {
        panic!("import circle between folders: {}", cycle.join(" -> "));
    }
}
