//! One line of a recording: its checksum (alone in version 1, chained in version 2), writing it
//! and checking and parsing it.
//!
//! A line's checksum is the low 32 bits of XXH3-64 over the line's text without its `sum`
//! field. In version 1 the hash has seed 0. In version 2 the seed is the previous line's
//! checksum (as a number), so each checksum also covers the one before it: a deleted,
//! duplicated or moved line breaks the chain at the next line. The chain starts after the
//! header: the header's checksum and the second line's seed are 0 in both versions, so a reader
//! can check the header before it knows the version.

use serde::Deserialize;

use super::{EventLine, Line};
use crate::input::{InputEvent, InvalidEvent};

/// Why one line of a recording is refused: its checksum or its content. Its `Display` is the
/// message without the line's number (the reader adds it).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum LineFormatError {
    /// The line does not end in a `sum` field.
    #[error("no checksum (\"sum\" field) at the end; the line is truncated or not a grove recording")]
    NoChecksum,
    /// The `sum` field is not 8 hex digits closed by `"}`.
    #[error("malformed checksum field; the line is truncated or corrupt")]
    MalformedChecksum,
    /// The checksum does not match; `chained` when it was chained on a previous line's.
    #[error("checksum mismatch: the line was changed or corrupted{}", if *chained { ", or a line before it was deleted, duplicated or moved" } else { "" })]
    ChecksumMismatch {
        /// Whether the checksum was chained on a previous line's (version 2, after the header's
        /// successor).
        chained: bool,
    },
    /// The JSON does not have the shape of a line: the first line of serde's message, without
    /// its position.
    #[error("{0}")]
    Json(String),
    /// A line read as an event whose `type` is something else.
    #[error("unexpected line type '{}'", .0.escape_debug())]
    UnexpectedType(String),
    /// A field in an event of a kind that has no fields.
    #[error("unknown field `{}` in an event of kind `{kind}`, which has no fields", field.escape_debug())]
    FieldInFieldlessEvent {
        /// The field.
        field: String,
        /// The event's kind.
        kind: String,
    },
    /// The event's numbers or names are refused.
    #[error(transparent)]
    Event(#[from] InvalidEvent),
}

impl From<serde_json::Error> for LineFormatError {
    fn from(e: serde_json::Error) -> Self {
        LineFormatError::Json(serde_message(e))
    }
}

/// The checksum of a line's text (without its `sum` field) with seed 0, as version 1 and every
/// header use: 8 hex digits.
pub fn line_sum(text: &str) -> String {
    format!("{:08x}", chained_sum(text, 0))
}

/// The checksum of a line's text (without its `sum` field) chained on the previous line's
/// checksum `prev` (0 for the header and the line after it, and for every line of version 1).
pub fn chained_sum(text: &str, prev: u32) -> u32 {
    xxhash_rust::xxh3::xxh3_64_with_seed(text.as_bytes(), prev as u64) as u32
}

const SUM_KEY: &str = ",\"sum\":\"";

/// Serializes a line with its seed-0 checksum (a header, or any line of version 1), without the
/// trailing newline.
pub fn encode_line(line: &Line) -> String {
    encode_line_chained(line, 0).0
}

/// Serializes a line with its checksum chained on `prev`, without the trailing newline; returns
/// the text and the line's checksum (the next line's `prev`).
pub fn encode_line_chained(line: &Line, prev: u32) -> (String, u32) {
    // Serializing these plain types to JSON cannot fail.
    let body = serde_json::to_string(line).unwrap_or_default();
    sign_body(&body, prev)
}

/// Adds the `sum` field to a line's JSON object text (`{...}` without a `sum`), chained on
/// `prev`; returns the line and its checksum.
pub fn sign_body(body: &str, prev: u32) -> (String, u32) {
    let sum = chained_sum(body, prev);
    let mut out = String::with_capacity(body.len() + 20);
    out.push_str(&body[..body.len().saturating_sub(1)]);
    out.push_str(SUM_KEY);
    out.push_str(&format!("{sum:08x}"));
    out.push_str("\"}");
    (out, sum)
}

/// Splits a line into its body (the object without the `sum` field, closed by `}`) and its
/// checksum, without checking the checksum.
pub fn split_sum(text: &str) -> Result<(String, u32), LineFormatError> {
    let text = text.trim_end_matches(['\r', '\n']);
    let (idx, sum) = sum_field(text)?;
    Ok((format!("{}}}", &text[..idx]), sum))
}

/// Turns a line into its body in place (the `sum` field cut off, the object closed by `}`), as
/// [`split_sum`] does without copying the text; returns the checksum.
pub fn split_sum_in_place(text: &mut String) -> Result<u32, LineFormatError> {
    // `trim_end_matches(['\r', '\n'])`, byte by byte (both are ASCII).
    let len = text.len() - text.bytes().rev().take_while(|b| matches!(b, b'\r' | b'\n')).count();
    text.truncate(len);
    let (idx, sum) = sum_field(text)?;
    text.truncate(idx);
    text.push('}');
    Ok(sum)
}

/// Where a line's `sum` field starts, and its value.
fn sum_field(text: &str) -> Result<(usize, u32), LineFormatError> {
    // The sum is always the last field: `,"sum":"` + 8 hex digits + `"}` = 18 bytes. Read as
    // bytes: where they match the key, its first byte is ASCII, so a character starts there,
    // and a byte that is not ASCII is no hex digit.
    let bytes = text.as_bytes();
    let idx =
        bytes.len().checked_sub(SUM_KEY.len() + 10).filter(|&i| bytes[i..i + SUM_KEY.len()] == *SUM_KEY.as_bytes());
    let idx = idx.ok_or(LineFormatError::NoChecksum)?;
    let tail = &bytes[idx + SUM_KEY.len()..];
    if tail[8..] != *b"\"}" {
        return Err(LineFormatError::MalformedChecksum);
    }
    // Each digit's value from a table (0x10 for a byte that is no hex digit), without a branch
    // per digit: the digits are random, so a branch would guess wrong half the time.
    let (mut sum, mut bad) = (0u32, 0u8);
    for &b in &tail[..8] {
        let digit = HEX_DIGIT[b as usize];
        bad |= digit;
        sum = sum << 4 | u32::from(digit & 0xf);
    }
    if bad & 0x10 != 0 {
        return Err(LineFormatError::MalformedChecksum);
    }
    Ok((idx, sum))
}

/// Each byte's value as a hex digit (either case), 0x10 for a byte that is none.
const HEX_DIGIT: [u8; 256] = {
    let mut t = [0x10u8; 256];
    let mut i = 0;
    while i < 10 {
        t[b'0' as usize + i] = i as u8;
        i += 1;
    }
    let mut i = 0;
    while i < 6 {
        t[b'a' as usize + i] = 10 + i as u8;
        t[b'A' as usize + i] = 10 + i as u8;
        i += 1;
    }
    t
};

/// Re-signs a whole recording's lines as version 2, each checksum chained on the one before
/// (the header's own checksum is unchanged in form). The bodies are kept as they are; this is
/// how `grove replay --upgrade` and the mutation tests forge a consistent chain.
pub fn rechain(lines: &[String]) -> Result<Vec<String>, LineFormatError> {
    let mut prev = 0;
    let mut out = Vec::with_capacity(lines.len());
    for (i, l) in lines.iter().enumerate() {
        let (body, _) = split_sum(l)?;
        let (text, sum) = sign_body(&body, prev);
        // The chain starts after the header.
        prev = if i == 0 { 0 } else { sum };
        out.push(text);
    }
    Ok(out)
}

/// An event line read directly (see [`decode_line`]).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct TaggedEvent {
    #[serde(rename = "type")]
    kind: String,
    tick: u64,
    ms: u64,
    frame: u64,
    event: serde_json::Value,
}

/// A controller-pose event line read directly (see [`decode_line`]).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct TaggedPose<'a> {
    #[serde(rename = "type", borrow)]
    kind: &'a str,
    tick: u64,
    ms: u64,
    frame: u64,
    #[serde(borrow)]
    event: PoseBody<'a>,
}

/// A checkpoint line read directly, without the buffering of the tagged [`Line`] enum.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct TaggedCheckpoint<'a> {
    #[serde(rename = "type", borrow)]
    kind: &'a str,
    tick: u64,
    hash: String,
    components: std::collections::BTreeMap<String, String>,
    entities: std::collections::BTreeMap<String, String>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct PoseBody<'a> {
    kind: &'a str,
    pose: crate::components::Pose,
}

/// The first line of a serde error, without its position (the caller names the line).
fn serde_message(e: serde_json::Error) -> String {
    let msg = e.to_string();
    msg.split(" at line ").next().unwrap_or(&msg).to_string()
}

/// Reads an input event from its JSON object, as an event line's `event` holds it, and checks
/// its numbers. Events without fields (`open_menu`, `close_menu`, `end_task`) are refused with
/// any field but `kind`, as every other event is with a field it does not have.
pub fn event_from_value(v: serde_json::Value) -> Result<InputEvent, LineFormatError> {
    if let serde_json::Value::Object(map) = &v
        && let Some(serde_json::Value::String(kind)) = map.get("kind")
        && matches!(kind.as_str(), "open_menu" | "close_menu" | "end_task")
        && let Some(extra) = map.keys().find(|k| *k != "kind")
    {
        return Err(LineFormatError::FieldInFieldlessEvent { field: extra.clone(), kind: kind.clone() });
    }
    let event: InputEvent = serde_json::from_value(v)?;
    event.validate()?;
    Ok(event)
}

/// Checks a line's seed-0 checksum (a header, or a line of version 1) and parses it.
pub fn decode_line(text: &str) -> Result<Line, LineFormatError> {
    decode_line_chained(text, 0)
}

/// Checks a line's checksum, chained on `prev` (see [`chained_sum`]), and parses it.
pub fn decode_line_chained(text: &str, prev: u32) -> Result<Line, LineFormatError> {
    decode_line_parts(text, prev).map(|(line, _, _)| line)
}

/// Like [`decode_line_chained`], and also returns the line's body (its text without the `sum`
/// field) and its checksum.
pub fn decode_line_parts(text: &str, prev: u32) -> Result<(Line, String, u32), LineFormatError> {
    decode_owned(text.to_string(), prev, Maps::Read)
}

/// Whether a checkpoint's per-component and per-entity hashes are read into its maps, or only
/// checked to be maps of strings (the maps left empty), for a reader that needs them only when
/// the world diverges and then reads the line again ([`parse_body`] with [`Maps::Read`]).
#[derive(Clone, Copy, PartialEq, Eq)]
pub(crate) enum Maps {
    Read,
    CheckOnly,
}

/// Like [`decode_line_parts`] on a line the caller owns, which becomes the returned body.
pub(crate) fn decode_owned(mut text: String, prev: u32, maps: Maps) -> Result<(Line, String, u32), LineFormatError> {
    let sum = split_sum_in_place(&mut text)?;
    if chained_sum(&text, prev) != sum {
        return Err(LineFormatError::ChecksumMismatch { chained: prev != 0 });
    }
    let line = parse_body(&text, maps)?;
    Ok((line, text, sum))
}

/// A JSON object of string values, checked without keeping it.
struct StringMap;

impl<'de> Deserialize<'de> for StringMap {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> serde::de::Visitor<'de> for V {
            type Value = StringMap;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a map")
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(self, mut m: A) -> Result<StringMap, A::Error> {
                while m.next_entry::<AString, AString>()?.is_some() {}
                Ok(StringMap)
            }
        }
        d.deserialize_map(V)
    }
}

/// A JSON string, checked without keeping it.
struct AString;

impl<'de> Deserialize<'de> for AString {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl serde::de::Visitor<'_> for V {
            type Value = AString;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a string")
            }
            fn visit_str<E: serde::de::Error>(self, _: &str) -> Result<AString, E> {
                Ok(AString)
            }
        }
        d.deserialize_str(V)
    }
}

/// A checkpoint line checked as [`TaggedCheckpoint`] reads it, keeping only its tick and hash.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct CheckedCheckpoint<'a> {
    #[serde(rename = "type", borrow)]
    kind: &'a str,
    tick: u64,
    hash: String,
    #[allow(dead_code)]
    components: StringMap,
    #[allow(dead_code)]
    entities: StringMap,
}

/// Parses a line's body once its checksum is known to be right.
pub(crate) fn parse_body(body: &str, maps: Maps) -> Result<Line, LineFormatError> {
    // Event lines are by far the most common: read them straight into their struct, without
    // the buffering that the tagged `Line` enum needs.
    if body.starts_with("{\"type\":\"event\",") {
        // Most lines are poses in the recorder's own shape: read without serde.
        if let Some(e) = super::fast_pose::read(body) {
            e.event.validate()?;
            return Ok(Line::Event(e));
        }
        // Controller poses are most of a recording: read them without the buffering that the
        // tagged `InputEvent` enum needs.
        if let Ok(e) = serde_json::from_str::<TaggedPose>(body)
            && e.kind == "event"
            && e.event.kind == "controller_pose"
        {
            let event = InputEvent::ControllerPose { pose: e.event.pose };
            event.validate()?;
            return Ok(Line::Event(EventLine { tick: e.tick, ms: e.ms, frame: e.frame, event }));
        }
        let e: TaggedEvent = serde_json::from_str(body)?;
        if e.kind != "event" {
            return Err(LineFormatError::UnexpectedType(e.kind));
        }
        let event = event_from_value(e.event)?;
        return Ok(Line::Event(EventLine { tick: e.tick, ms: e.ms, frame: e.frame, event }));
    }
    // Checkpoints come next, once a second of a recording: in the recorder's own shape read
    // without serde.
    if maps == Maps::CheckOnly
        && let Some(c) = super::fast_checkpoint::read(body)
    {
        return Ok(Line::Checkpoint(c));
    }
    if maps == Maps::CheckOnly
        && body.starts_with("{\"type\":\"checkpoint\",")
        && let Ok(c) = serde_json::from_str::<CheckedCheckpoint>(body)
        && c.kind == "checkpoint"
    {
        let (components, entities) = Default::default();
        return Ok(Line::Checkpoint(super::CheckpointLine { tick: c.tick, hash: c.hash, components, entities }));
    }
    if body.starts_with("{\"type\":\"checkpoint\",")
        && let Ok(c) = serde_json::from_str::<TaggedCheckpoint>(body)
        && c.kind == "checkpoint"
    {
        return Ok(Line::Checkpoint(super::CheckpointLine {
            tick: c.tick,
            hash: c.hash,
            components: c.components,
            entities: c.entities,
        }));
    }
    let line: Line = serde_json::from_str(body)?;
    if let Line::Event(ev) = &line {
        // Read the event again from its JSON object, for the checks `event_from_value` makes.
        let v: serde_json::Value = serde_json::from_str(body)?;
        event_from_value(v.get("event").cloned().unwrap_or_default())?;
        ev.event.validate()?;
    }
    Ok(line)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `sum_field` as it read the field through `str` methods, the reference for the bytes.
    fn sum_field_by_str(text: &str) -> Result<(usize, u32), LineFormatError> {
        let idx = text
            .len()
            .checked_sub(SUM_KEY.len() + 10)
            .filter(|&i| text.is_char_boundary(i) && text[i..].starts_with(SUM_KEY));
        let idx = idx.ok_or(LineFormatError::NoChecksum)?;
        let tail = &text[idx + SUM_KEY.len()..];
        if !tail.ends_with("\"}") {
            return Err(LineFormatError::MalformedChecksum);
        }
        let sum = tail.get(..8).and_then(|s| {
            if s.bytes().all(|b| b.is_ascii_hexdigit()) { u32::from_str_radix(s, 16).ok() } else { None }
        });
        Ok((idx, sum.ok_or(LineFormatError::MalformedChecksum)?))
    }

    #[test]
    fn the_sum_field_read_as_bytes_is_read_as_through_str() {
        let good = r#"{"type":"event","tick":3,"ms":50,"frame":3,"event":{"kind":"end_task"},"sum":"4a8E43f9"}"#;
        assert_eq!(sum_field(good), Ok((good.len() - 18, 0x4a8e_43f9)));
        // Every byte of the field's last 24 replaced by others (ASCII, a 2-, 3- and 4-byte
        // character), cut short, or lengthened.
        let mut cases = vec![
            String::new(),
            "}".into(),
            good[..good.len() - 1].to_string(),
            format!("{good}}}"),
            format!("é{good}"),
        ];
        for at in good.len() - 24..good.len() {
            for with in ["0", "9", "a", "f", "g", "A", "F", "G", "\"", "}", ",", " ", "é", "€", "😀", ""] {
                cases.push(format!("{}{with}{}", &good[..at], &good[at + 1..]));
            }
        }
        for text in &cases {
            assert_eq!(sum_field(text), sum_field_by_str(text), "{text}");
        }
    }

    #[test]
    fn a_checkpoint_read_without_its_maps_is_checked_as_strictly_as_with_them() {
        let good = r#"{"type":"checkpoint","tick":60,"hash":"00000000000000aa","components":{"Tree":"0000000000000001"},"entities":{"4294967296":"0000000000000002"}}"#;
        let Ok(Line::Checkpoint(full)) = parse_body(good, Maps::Read) else { panic!("a good checkpoint") };
        let Ok(Line::Checkpoint(light)) = parse_body(good, Maps::CheckOnly) else { panic!("a good checkpoint") };
        assert_eq!((light.tick, &light.hash), (full.tick, &full.hash));
        assert_eq!(full.components.get("Tree").map(String::as_str), Some("0000000000000001"));
        assert!(light.components.is_empty() && light.entities.is_empty());
        // Whatever the full reading refuses, the light one refuses with the same message.
        for bad in [
            r#"{"type":"checkpoint","tick":60,"hash":"aa","components":{"Tree":5},"entities":{}}"#,
            r#"{"type":"checkpoint","tick":60,"hash":"aa","components":{},"entities":[]}"#,
            r#"{"type":"checkpoint","tick":60,"hash":"aa","components":{}}"#,
            r#"{"type":"checkpoint","tick":60,"hash":"aa","components":{},"entities":{},"extra":1}"#,
            r#"{"type":"checkpoint","tick":-1,"hash":"aa","components":{},"entities":{}}"#,
        ] {
            let a = parse_body(bad, Maps::Read).err().map(|e| e.to_string());
            let b = parse_body(bad, Maps::CheckOnly).err().map(|e| e.to_string());
            assert!(a.is_some(), "{bad}");
            assert_eq!(a, b, "{bad}");
        }
    }
}
