//! The rules a protocol file must keep, each failure naming its place: the conditions (built-in
//! tasks, a participant count the balanced Latin square balances), the blocks (none empty, every
//! file inside the protocol's folder, every questionnaire one that exists) and the instruments
//! (items of known kinds, scales with their anchors, scoring that fits its items).

use std::path::Path;

use super::format::{Block, Instrument, ItemKind, Protocol, Scoring};
use super::shipped;

/// A rule broken: where, and what.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Broken {
    /// The place, e.g. `block 3 'practice'`.
    pub place: String,
    /// What is wrong, one line.
    pub message: String,
}

fn broken(place: impl Into<String>, message: impl Into<String>) -> Broken {
    Broken { place: place.into(), message: message.into() }
}

/// Whether `s` is a word: 1 to 32 letters, digits, `-` or `_`.
pub fn is_word(s: &str) -> bool {
    !s.is_empty() && s.len() <= 32 && s.bytes().all(|b| b.is_ascii_alphanumeric() || b == b'-' || b == b'_')
}

/// The most choices an item may offer.
pub const MAX_CHOICES: usize = 50;
/// The most characters a free-text item may allow.
pub const MAX_TEXT_CHARS: usize = 10_000;
/// The most answers a scale may have.
pub const MAX_SCALE_STEPS: i64 = 1000;
/// The longest practice, seconds.
pub const MAX_PRACTICE_S: f64 = 3600.0;

/// Checks a protocol; `folder` is the protocol file's folder (instruction files lie inside it).
pub fn check(p: &Protocol, folder: &Path) -> Result<(), Broken> {
    if !is_word(&p.name) {
        return Err(broken("name", format!("'{}' is not a name (1 to 32 letters, digits, '-' or '_')", p.name)));
    }
    if grove_systems::scene::Scene::builtin(&p.scene).is_none() {
        let known: Vec<&str> = grove_systems::scene::BUILTIN_SCENES.iter().map(|(n, _)| *n).collect();
        return Err(broken("scene", format!("'{}' is not a built-in scene (known: {})", p.scene, known.join(", "))));
    }
    conditions(p)?;
    for ins in &p.instruments {
        if shipped::get(&ins.id).is_some() {
            return Err(broken(
                format!("instrument '{}'", ins.id),
                "is the id of a shipped instrument; use it without declaring it, or give yours another id",
            ));
        }
        instrument(ins)?;
    }
    for (i, a) in p.instruments.iter().enumerate() {
        if p.instruments[..i].iter().any(|b| b.id == a.id) {
            return Err(broken(format!("instrument '{}'", a.id), "is declared twice"));
        }
    }
    blocks(p, folder)?;
    for (i, c) in p.compare.iter().enumerate() {
        for side in [&c.a, &c.b] {
            if !is_numeric_item(p, side) {
                return Err(broken(
                    format!("compare {}", i + 1),
                    format!(
                        "'{side}' is not 'instrument/item' of a numeric item (rating, scale or Likert) of a questionnaire the protocol gives"
                    ),
                ));
            }
        }
    }
    Ok(())
}

fn conditions(p: &Protocol) -> Result<(), Broken> {
    if p.conditions.is_empty() {
        return Err(broken("conditions", "none: a protocol needs at least one condition"));
    }
    for (i, c) in p.conditions.iter().enumerate() {
        let place = format!("condition {} '{}'", i + 1, c.name);
        if !is_word(&c.name) {
            return Err(broken(place, "the name must be 1 to 32 letters, digits, '-' or '_'"));
        }
        if p.conditions[..i].iter().any(|d| d.name == c.name) {
            return Err(broken(place, "is named twice"));
        }
        if grove_systems::task::TaskDef::builtin(&c.task).is_none() {
            let known: Vec<&str> = grove_systems::task::BUILTIN_TASKS.iter().map(|(id, _)| *id).collect();
            return Err(broken(place, format!("task '{}' does not exist (the tasks: {})", c.task, known.join(", "))));
        }
    }
    let rows = super::latin::williams(p.conditions.len()).len();
    if p.participants == 0 || !p.participants.is_multiple_of(rows) || p.participants > 10_000 {
        return Err(broken(
            "participants",
            format!(
                "a balanced Latin square of {} conditions has {rows} rows, so it balances a multiple of {rows} participants ({rows}, {}, {}, …); the protocol has {}",
                p.conditions.len(),
                2 * rows,
                3 * rows,
                p.participants
            ),
        ));
    }
    Ok(())
}

fn blocks(p: &Protocol, folder: &Path) -> Result<(), Broken> {
    if p.blocks.is_empty() {
        return Err(broken("blocks", "none: a protocol needs at least one block"));
    }
    let mut tasks = 0;
    for (i, b) in p.blocks.iter().enumerate() {
        let place = format!("block {} '{}'", i + 1, b.name());
        if !is_word(b.name()) {
            return Err(broken(place, "the name must be 1 to 32 letters, digits, '-' or '_'"));
        }
        if p.blocks[..i].iter().any(|c| c.name() == b.name()) {
            return Err(broken(place, "is named twice"));
        }
        match b {
            Block::Instructions { text, image, video, .. } => {
                if text.trim().is_empty() && image.is_none() && video.is_none() {
                    return Err(broken(place, "an empty block: instructions need a text, an image or a video"));
                }
                for f in [image, video].into_iter().flatten() {
                    grove_systems::files::within(&folder.join(f), folder)
                        .map_err(|e| broken(place.clone(), e.reason()))?;
                }
            }
            Block::Practice { seconds, .. } => {
                if let Some(s) = seconds
                    && !(s.is_finite() && *s > 0.0 && *s <= MAX_PRACTICE_S)
                {
                    return Err(broken(place, format!("seconds must be above 0 and at most {MAX_PRACTICE_S}")));
                }
            }
            Block::Tasks { after, .. } => {
                tasks += 1;
                if tasks > 1 {
                    return Err(broken(
                        place,
                        "a second Tasks block: the conditions' tasks are one block, done once in each participant's order",
                    ));
                }
                for id in after {
                    questionnaire(p, id).map_err(|m| broken(place.clone(), m))?;
                }
            }
            Block::Questionnaire { instrument, .. } => questionnaire(p, instrument).map_err(|m| broken(place, m))?,
        }
    }
    Ok(())
}

/// An instrument the protocol may give: its own, or a shipped one.
fn questionnaire(p: &Protocol, id: &str) -> Result<(), String> {
    match p.instruments.iter().find(|i| i.id == id).cloned().or_else(|| shipped::get(id)) {
        None => Err(format!(
            "questionnaire '{id}' does not exist (the protocol's: {}; shipped: {})",
            p.instruments.iter().map(|i| i.id.as_str()).collect::<Vec<_>>().join(", "),
            shipped::IDS.join(", ")
        )),
        Some(i) if i.items.is_empty() => Err(format!("an empty block: questionnaire '{id}' has no items")),
        Some(_) => Ok(()),
    }
}

fn is_numeric_item(p: &Protocol, path: &str) -> bool {
    let Some((ins, item)) = path.split_once('/') else { return false };
    let given = p.blocks.iter().any(|b| match b {
        Block::Questionnaire { instrument, .. } => instrument == ins,
        Block::Tasks { after, .. } => after.iter().any(|a| a == ins),
        _ => false,
    });
    let found = p.instruments.iter().find(|i| i.id == ins).cloned().or_else(|| shipped::get(ins));
    given
        && found.is_some_and(|i| {
            i.items.iter().any(|it| {
                it.id == item
                    && matches!(it.kind, ItemKind::Rating { .. } | ItemKind::Scale { .. } | ItemKind::Likert { .. })
            })
        })
}

/// Checks one instrument.
pub fn instrument(ins: &Instrument) -> Result<(), Broken> {
    let place = format!("instrument '{}'", ins.id);
    if !is_word(&ins.id) {
        return Err(broken(place, "the id must be 1 to 32 letters, digits, '-' or '_'"));
    }
    if ins.items.is_empty() {
        return Err(broken(place, "an empty questionnaire: it has no items"));
    }
    for (n, item) in ins.items.iter().enumerate() {
        let at = format!("instrument '{}', item {} '{}'", ins.id, n + 1, item.id);
        if !is_word(&item.id) {
            return Err(broken(at, "the id must be 1 to 32 letters, digits, '-' or '_'"));
        }
        if ins.items[..n].iter().any(|o| o.id == item.id) {
            return Err(broken(at, "the id is used twice"));
        }
        if item.text.trim().is_empty() {
            return Err(broken(at, "the item has no question text"));
        }
        kind(&item.kind).map_err(|m| broken(at, m))?;
    }
    let fits = match ins.scoring {
        Scoring::None => Ok(()),
        Scoring::Sus => {
            if ins.items.len() == 10
                && ins.items.iter().all(|i| matches!(i.kind, ItemKind::Likert { points: 5, .. }) && i.required)
            {
                Ok(())
            } else {
                Err("Sus scoring needs ten required 5-point Likert items")
            }
        }
        Scoring::RawTlx => {
            if ins.items.len() == 6
                && ins
                    .items
                    .iter()
                    .all(|i| matches!(i.kind, ItemKind::Scale { .. } | ItemKind::Rating { .. }) && i.required)
            {
                Ok(())
            } else {
                Err("RawTlx scoring needs six required scale items (the six subscales)")
            }
        }
    };
    fits.map_err(|m| broken(format!("instrument '{}', scoring", ins.id), m))
}

fn anchors_named(anchors: &[String]) -> bool {
    anchors.iter().all(|a| !a.trim().is_empty())
}

fn kind(k: &ItemKind) -> Result<(), String> {
    match k {
        ItemKind::Rating { anchors } => {
            if anchors.len() != 2 || !anchors_named(anchors) {
                return Err(
                    "a 0–10 rating needs its anchors: the words at 0 and at 10 (anchors: [\"…\", \"…\"])".into()
                );
            }
        }
        ItemKind::Scale { min, max, step, anchors } => {
            if anchors.len() != 2 || !anchors_named(anchors) {
                return Err("a scale needs its anchors: the words at its two ends (anchors: [\"…\", \"…\"])".into());
            }
            if min >= max
                || *step <= 0
                || (max - min) % step != 0
                || (max - min) / step > MAX_SCALE_STEPS
                || min.abs() > 1_000_000
                || max.abs() > 1_000_000
            {
                return Err(format!(
                    "a scale from {min} to {max} in steps of {step}: min must be below max, and (max − min) a multiple of the step, at most {MAX_SCALE_STEPS} steps"
                ));
            }
        }
        ItemKind::Likert { points, anchors } => {
            if !(2..=11).contains(points) {
                return Err(format!("a Likert item has 2 to 11 points, not {points}"));
            }
            if !(anchors.len() == 2 || anchors.len() as i64 == *points) || !anchors_named(anchors) {
                return Err(format!(
                    "a Likert scale needs its anchors: the words at its two ends, or one for each of its {points} points"
                ));
            }
        }
        ItemKind::Single { choices } | ItemKind::Multiple { choices } => {
            if choices.is_empty() || choices.len() > MAX_CHOICES {
                return Err(format!("a choice item needs 1 to {MAX_CHOICES} choices"));
            }
            for (i, c) in choices.iter().enumerate() {
                if c.trim().is_empty() || c.chars().count() > 200 {
                    return Err(format!("choice {} is empty or longer than 200 characters", i + 1));
                }
                if choices[..i].contains(c) {
                    return Err(format!("choice '{c}' is offered twice"));
                }
            }
        }
        ItemKind::Text { max_chars } => {
            if *max_chars == 0 || *max_chars > MAX_TEXT_CHARS {
                return Err(format!("max_chars must be 1 to {MAX_TEXT_CHARS}"));
            }
        }
        ItemKind::YesNo => {}
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    #[test]
    fn every_shipped_instrument_parses_and_keeps_the_rules() {
        for id in super::shipped::IDS {
            let ins = super::shipped::get(id).unwrap_or_else(|| panic!("{id} does not parse"));
            assert_eq!(ins.id, *id);
            super::instrument(&ins).unwrap_or_else(|b| panic!("{id}: {}: {}", b.place, b.message));
        }
    }
}
