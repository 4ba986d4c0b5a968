//! The rules a recording's lines keep, checked one line at a time: the header first (its
//! checksum, format and version), then for every later line its checksum (chained from version 2
//! on), its place (nothing after the footer, no second header) and its tick (never decreasing,
//! within [`MAX_TICKS`], at most [`CHECKPOINT_EVERY`] past the last checkpoint).
//!
//! The file reader ([`super::lines`]) feeds every line it reads through these rules; a session
//! server feeds each line as it arrives. A line that breaks a rule leaves the rules' state as it
//! was, so the stream may go on from the last good line.

use super::codec::{Maps, decode_line_chained, decode_owned};
use super::{CHECKPOINT_EVERY, FORMAT_NAME, Header, Line, READABLE_VERSIONS};
use crate::limits::{MAX_TICKS, RAISE};

crate::message_error::message_error! {
    /// Why a line of a recording breaks the format's rules: one line of text, without the line's
    /// number (the caller adds it).
    LineRuleError
}

/// Checks a recording's first line and returns its header: a `header` line of a readable
/// version and of the grove format, with a right checksum (seed 0).
pub fn header_line(text: &str) -> Result<Header, LineRuleError> {
    let fail = |m: String| LineRuleError(m);
    // Look at the type and version before the checksum, so a file without a header or of a
    // future format gets a clear message.
    if let Ok(v) = serde_json::from_str::<serde_json::Value>(text.trim()) {
        if v.get("type").and_then(|t| t.as_str()) != Some("header") {
            return Err(fail("missing header: the first line must be the recording header".into()));
        }
        if let Some(ver) = v.get("format_version").and_then(|x| x.as_u64())
            && !READABLE_VERSIONS.iter().any(|&r| r as u64 == ver)
        {
            return Err(fail(format!(
                "format version {ver} is not supported; this grove reads versions {READABLE_VERSIONS:?} (upgrade grove to read newer files)"
            )));
        }
    }
    let header = match decode_line_chained(text, 0).map_err(|m| fail(m.to_string()))? {
        Line::Header(h) => h,
        _ => return Err(fail("missing header: the first line must be the recording header".into())),
    };
    if header.format != FORMAT_NAME {
        return Err(fail(format!("format {:?} is not '{FORMAT_NAME}'", header.format)));
    }
    Ok(header)
}

/// One line that kept the rules.
#[derive(Debug)]
pub struct RuledLine {
    /// The parsed line.
    pub line: Line,
    /// Its tick (an event's or checkpoint's `tick`, the footer's `final_tick`).
    pub tick: u64,
    /// Its text without the `sum` field.
    pub body: String,
}

/// The state of the rules after the header and the lines checked so far.
#[derive(Clone)]
pub struct LineRules {
    /// Whether checksums are chained (version 2 and later).
    chained: bool,
    prev: u32,
    last_tick: u64,
    last_checkpoint: u64,
    footer_seen: bool,
    maps: Maps,
}

impl LineRules {
    /// The rules for the lines after this header.
    pub fn after(header: &Header) -> LineRules {
        LineRules {
            chained: header.format_version >= 2,
            prev: 0,
            last_tick: 0,
            last_checkpoint: 0,
            footer_seen: false,
            maps: Maps::Read,
        }
    }

    /// From now on a checkpoint's per-component and per-entity maps are checked but left empty
    /// (see [`super::codec::parse_body`]).
    pub(crate) fn checkpoint_maps_when_needed(&mut self) {
        self.maps = Maps::CheckOnly;
    }

    /// Whether the footer has been checked (nothing may follow it).
    pub fn footer_seen(&self) -> bool {
        self.footer_seen
    }

    /// The tick of the last line checked (0 before any).
    pub fn last_tick(&self) -> u64 {
        self.last_tick
    }

    /// Checks the next line (its text without the newline) and, when it keeps every rule,
    /// advances the state past it. A line that breaks one leaves the state unchanged.
    pub fn check(&mut self, text: String) -> Result<RuledLine, LineRuleError> {
        let fail = |m: String| LineRuleError(m);
        if text.trim().is_empty() {
            return Err(fail("empty line".into()));
        }
        if self.footer_seen {
            return Err(fail("a line after the footer".into()));
        }
        let prev = if self.chained { self.prev } else { 0 };
        let (line, body, sum) = decode_owned(text, prev, self.maps).map_err(|m| fail(m.to_string()))?;
        let tick = match &line {
            Line::Header(_) => return Err(fail("a second header".into())),
            Line::Event(e) => e.tick,
            Line::Checkpoint(c) => c.tick,
            Line::Footer(f) => f.final_tick,
        };
        if tick > MAX_TICKS {
            return Err(fail(format!(
                "tick {tick} is past the limit of {MAX_TICKS} ticks per recording (about 19 days at 60 Hz; {RAISE})"
            )));
        }
        if tick < self.last_tick {
            return Err(fail(format!("tick {tick} comes after tick {}: ticks out of order", self.last_tick)));
        }
        if tick > self.last_checkpoint + CHECKPOINT_EVERY {
            return Err(fail(format!(
                "tick {tick} is more than {CHECKPOINT_EVERY} ticks past the last checkpoint (tick {}); a checkpoint is missing",
                self.last_checkpoint
            )));
        }
        self.prev = sum;
        if let Line::Checkpoint(_) = &line {
            self.last_checkpoint = tick;
        }
        if let Line::Footer(_) = &line {
            self.footer_seen = true;
        }
        self.last_tick = tick;
        Ok(RuledLine { line, tick, body })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn study_lines() -> Vec<String> {
        let file = include_str!("../../../replays/scenarios/plant-two.jsonl");
        file.lines().map(str::to_string).collect()
    }

    #[test]
    fn a_refused_line_leaves_the_rules_where_they_were() {
        let lines = study_lines();
        let header = header_line(&lines[0]).unwrap();
        let mut rules = LineRules::after(&header);
        rules.check(lines[1].clone()).unwrap();
        // A changed line, a line skipped and a second header are refused ...
        let flipped = lines[2].replacen("\"tick\":1", "\"tick\":2", 1);
        assert_ne!(flipped, lines[2]);
        assert!(rules.check(flipped).unwrap_err().0.contains("checksum mismatch"));
        assert!(rules.check(lines[3].clone()).unwrap_err().0.contains("checksum mismatch"), "the chain misses line 3");
        assert!(rules.check(lines[0].clone()).is_err(), "a second header");
        // ... and the stream goes on from the last good line as if they had not come.
        let mut fresh = LineRules::after(&header);
        fresh.check(lines[1].clone()).unwrap();
        for l in &lines[2..] {
            let a = rules.check(l.clone()).map(|r| r.tick).map_err(|e| e.0);
            let b = fresh.check(l.clone()).map(|r| r.tick).map_err(|e| e.0);
            assert_eq!(a, b);
            assert!(a.is_ok(), "{l}");
        }
        assert!(rules.footer_seen());
        assert_eq!(rules.check(lines[1].clone()).unwrap_err().0, "a line after the footer");
    }

    #[test]
    fn a_header_of_another_kind_or_version_is_refused_by_name() {
        let lines = study_lines();
        assert!(header_line(&lines[1]).unwrap_err().0.starts_with("missing header"));
        let future = lines[0].replacen("\"format_version\":2", "\"format_version\":9", 1);
        assert_ne!(future, lines[0]);
        assert!(header_line(&future).unwrap_err().0.contains("format version 9"));
    }
}
