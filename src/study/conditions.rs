//! Studies with k ≥ 3 conditions (techniques): per participant and condition the task time,
//! the Friedman test with post-hoc pairwise comparisons ([`super::friedman`]), and the order
//! effects, the task times by block position. Two conditions keep the paired analysis of
//! [`super::report`] unchanged; this section is absent for them.

use serde::Serialize;

use super::Trial;
use super::friedman::{Conditions, analyse, markdown};

/// Task times at one block position, over every condition.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Position {
    /// The block, 1-based.
    pub block: u32,
    /// Completed trials in that block.
    pub n: usize,
    /// Their mean task time, seconds.
    pub mean_time_s: f64,
}

/// The k-condition section of a study summary.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct KConditions {
    /// The conditions: ray-casting and manual first, then the plug-ins by name.
    pub conditions: Vec<String>,
    /// Participants with a usable time in every condition (the Friedman test's blocks).
    pub complete_participants: usize,
    /// Participants left out for a missing or unusable condition.
    pub left_out: Vec<String>,
    /// The tests, when at least two participants are complete.
    pub analysis: Option<Conditions>,
    /// Order effects: the task time by block position.
    pub by_block: Vec<Position>,
}

/// The trial's condition: its technique (the task report's mode).
fn condition(t: &Trial) -> Option<&str> {
    t.task.as_ref().map(|k| k.mode.as_str())
}

/// The section for `trials`, or `None` with fewer than three conditions. `usable_time` is a
/// trial's task time when it counts (the report's rule).
pub fn k_conditions(trials: &[Trial], usable_time: fn(&Trial) -> Option<f64>) -> Option<KConditions> {
    let mut conditions: Vec<String> = Vec::new();
    for t in trials {
        if let Some(c) = condition(t) {
            if !conditions.iter().any(|x| x == c) {
                conditions.push(c.to_string());
            }
        }
    }
    if conditions.len() < 3 {
        return None;
    }
    let rank = |c: &String| match c.as_str() {
        "ray-casting" => (0, c.clone()),
        "manual" => (1, c.clone()),
        _ => (2, c.clone()),
    };
    conditions.sort_by_key(rank);
    let mut participants: Vec<&str> = trials.iter().map(|t| t.participant.as_str()).collect();
    participants.sort_unstable();
    participants.dedup();
    let (mut rows, mut left_out) = (Vec::new(), Vec::new());
    for p in participants {
        let row: Option<Vec<f64>> = conditions
            .iter()
            .map(|c| {
                trials.iter().find(|t| t.participant == p && condition(t) == Some(c.as_str())).and_then(usable_time)
            })
            .collect();
        match row {
            Some(r) => rows.push(r),
            None => left_out.push(p.to_string()),
        }
    }
    let mut by_block = Vec::new();
    let blocks = trials.iter().map(|t| t.block_num).max().unwrap_or(0);
    for block in 1..=blocks {
        let times: Vec<f64> = trials.iter().filter(|t| t.block_num == block).filter_map(usable_time).collect();
        if !times.is_empty() {
            by_block.push(Position {
                block,
                n: times.len(),
                mean_time_s: times.iter().sum::<f64>() / times.len() as f64,
            });
        }
    }
    Some(KConditions {
        complete_participants: rows.len(),
        analysis: analyse(&conditions, &rows, "s"),
        conditions,
        left_out,
        by_block,
    })
}

/// The section as text for the terminal and the report (Markdown).
pub fn lines(k: &KConditions) -> String {
    let mut s = match &k.analysis {
        Some(a) => markdown(a, "task time"),
        None => format!(
            "### task time: {} conditions\n\nFewer than two participants have every condition; no test.\n",
            k.conditions.len()
        ),
    };
    if !k.left_out.is_empty() {
        s += &format!("\nLeft out (a condition missing or unusable): {}.\n", k.left_out.join(", "));
    }
    s += "\nOrder effects (conditions counterbalanced by a balanced Latin square):\n\n| block | trials | mean time (s) |\n|---|---|---|\n";
    for b in &k.by_block {
        s += &format!("| {} | {} | {:.2} |\n", b.block, b.n, b.mean_time_s);
    }
    s
}
