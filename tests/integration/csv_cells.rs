//! CSV injection (`docs/reports.md`, "Cells a spreadsheet could run"): a participant's free-text
//! answer `=HYPERLINK("x")` is text in every CSV `grove study` writes, and no cell of any of them
//! begins as a formula; numbers, negative ones included, stay numbers.

use crate::common::{grove, root, scratch};

/// Whether a cell is a plain number (`-1.5`, `+3`, `2.5e-4`), which a spreadsheet reads as one.
fn is_number(cell: &str) -> bool {
    cell.parse::<f64>().is_ok_and(f64::is_finite) && cell.bytes().all(|b| b.is_ascii_digit() || b"+-.eE".contains(&b))
}

#[test]
fn a_formula_as_a_free_text_answer_is_text_in_every_csv_the_study_writes() {
    let dir = scratch("csv-injection");
    let protocol = std::fs::read_to_string(root().join("assets/protocols/tree-planting.ron")).unwrap();
    std::fs::write(dir.join("protocol.ron"), &protocol).unwrap();
    std::fs::copy(root().join("replays/study/P01-manual-7.jsonl"), dir.join("P01-manual-7-1.jsonl")).unwrap();
    let answers = [
        r#"{"line":"participant","participant":"P01","protocol":"tree-planting","index":0,"order":["ray-casting","manual"],"time":"2026-12-01T09:00:00.000Z"}"#.to_string(),
        serde_json::json!({"line": "answer", "step": 7, "block": "questions", "instrument": "tree-planting", "condition": null, "item": "uses", "answer": "=HYPERLINK(\"x\")", "time": "2026-12-01T09:20:00.000Z"}).to_string(),
        serde_json::json!({"line": "answer", "step": 7, "block": "questions", "instrument": "tree-planting", "condition": null, "item": "guidance", "answer": 8, "time": "2026-12-01T09:20:00.000Z"}).to_string(),
    ];
    std::fs::write(dir.join("P01.answers.jsonl"), answers.iter().map(|l| format!("{l}\n")).collect::<String>()).unwrap();
    let out = dir.join("report");
    let run = grove(&["study", "--replays", &dir.display().to_string(), "--out", &out.display().to_string()]);
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let mut csvs: Vec<std::path::PathBuf> = std::fs::read_dir(&out).unwrap().map(|e| e.unwrap().path()).filter(|p| p.extension().is_some_and(|e| e == "csv")).collect();
    csvs.sort();
    let names: Vec<String> = csvs.iter().map(|p| p.file_name().unwrap().to_string_lossy().into_owned()).collect();
    assert_eq!(names, ["questionnaire_long.csv", "questionnaire_scores.csv", "questionnaire_wide.csv", "trees.csv", "trial_results.csv"]);
    let mut numbers = 0;
    for path in &csvs {
        let mut found = false;
        for record in csv::ReaderBuilder::new().has_headers(false).from_path(path).unwrap().records() {
            for cell in record.unwrap().iter() {
                if cell.starts_with(['=', '+', '-', '@', '\t', '\r']) {
                    assert!(is_number(cell), "{}: a cell begins as a formula: {cell:?}", path.display());
                    numbers += 1;
                }
                found |= cell == "'=HYPERLINK(\"x\")";
            }
        }
        let holds_answers = names.iter().zip(&csvs).any(|(n, p)| p == path && (n == "questionnaire_long.csv" || n == "questionnaire_wide.csv"));
        assert_eq!(found, holds_answers, "{}: the answer as text", path.display());
    }
    assert!(numbers > 0, "negative numbers (the trees' coordinates) are written as numbers");
}
