//! The checkpoint line read without serde, when only its tick and hash are kept (the reader
//! reads the per-component and per-entity maps again at a divergence) and it has exactly the
//! shape the recorder writes:
//!
//! ```text
//! {"type":"checkpoint","tick":T,"hash":"H","components":{"K":"V",…},"entities":{"K":"V",…}}
//! ```
//!
//! with every string made of printable ASCII other than `"` and `\` (no escapes). serde reads
//! such a line to the same tick and hash and accepts it as a whole; anything else (spacing,
//! field order, escapes, other characters, numbers this reader does not take) returns `None`,
//! and the line is read by serde as before. Checkpoints are one line in eight of a study's
//! recordings, and their maps were most of the parsing left after the pose lines.

use super::CheckpointLine;
use super::fast_pose::Cursor;

/// The bytes a plain string may hold: printable ASCII other than `"` and `\`.
const PLAIN: [bool; 256] = {
    let mut t = [false; 256];
    let mut b = b' ';
    while b <= b'~' {
        t[b as usize] = b != b'"' && b != b'\\';
        b += 1;
    }
    t
};

impl Cursor<'_> {
    /// A JSON string without escapes, of printable ASCII: where its text starts and ends.
    fn plain_string(&mut self) -> Option<(usize, usize)> {
        self.byte(b'"')?;
        let start = self.at;
        while self.s.get(self.at).is_some_and(|&b| PLAIN[b as usize]) {
            self.at += 1;
        }
        let end = self.at;
        self.byte(b'"')?;
        Some((start, end))
    }

    /// An object of plain strings, checked without keeping it.
    fn string_map(&mut self) -> Option<()> {
        self.byte(b'{')?;
        if self.byte(b'}').is_some() {
            return Some(());
        }
        loop {
            self.plain_string()?;
            self.byte(b':')?;
            self.plain_string()?;
            if self.byte(b'}').is_some() {
                return Some(());
            }
            self.byte(b',')?;
        }
    }
}

/// The checkpoint with empty maps, if `body` (a line without its `sum` field) is one in the
/// recorder's own shape; `None` otherwise, for serde to read.
pub(super) fn read(body: &str) -> Option<CheckpointLine> {
    let mut c = Cursor { s: body.as_bytes(), at: 0 };
    c.lit("{\"type\":\"checkpoint\",\"tick\":")?;
    let tick = c.uint()?;
    c.lit(",\"hash\":")?;
    let (start, end) = c.plain_string()?;
    let hash = std::str::from_utf8(&c.s[start..end]).ok()?.to_string();
    c.lit(",\"components\":")?;
    c.string_map()?;
    c.lit(",\"entities\":")?;
    c.string_map()?;
    c.byte(b'}')?;
    if c.at != body.len() {
        return None;
    }
    Some(CheckpointLine { tick, hash, components: Default::default(), entities: Default::default() })
}

#[cfg(test)]
mod tests {
    use super::super::Line;
    use super::super::codec::{Maps, parse_body};
    use super::*;

    const GOOD: &str = r#"{"type":"checkpoint","tick":60,"hash":"1aecc9c608920b40","components":{"AnchorBall":"468164055b7c42fd","Tree":"f262b8d91b956498"},"entities":{"4294967296":"434800c22c663003"}}"#;

    #[test]
    fn a_checkpoint_in_the_recorders_shape_reads_as_serde_reads_it() {
        for body in [
            GOOD.to_string(),
            GOOD.replace(r#"{"AnchorBall":"468164055b7c42fd","Tree":"f262b8d91b956498"}"#, "{}"),
            GOOD.replace("\"tick\":60", "\"tick\":0"),
        ] {
            let fast = read(&body).unwrap_or_else(|| panic!("read: {body}"));
            let Ok(Line::Checkpoint(full)) = parse_body(&body, Maps::Read) else { panic!("serde reads {body}") };
            assert_eq!((fast.tick, &fast.hash), (full.tick, &full.hash), "{body}");
            assert!(fast.components.is_empty() && fast.entities.is_empty());
        }
    }

    #[test]
    fn anything_but_the_recorders_own_shape_is_left_to_serde() {
        assert!(read(GOOD).is_some());
        for bad in [
            GOOD.replace("\"tick\":60", "\"tick\": 60"),
            GOOD.replace("\"tick\":60", "\"tick\":060"),
            GOOD.replace("\"tick\":60", "\"tick\":-1"),
            GOOD.replace("\"tick\":60", "\"tick\":99999999999999999999"),
            GOOD.replace("1aecc9c608920b40", "1aecc9c6\\u0030"),
            GOOD.replace("AnchorBall", "Anchor\\\"Ball"),
            GOOD.replace("AnchorBall", "Anchorbäll"),
            GOOD.replace(":\"468164055b7c42fd\"", ":5"),
            GOOD.replace(",\"Tree\"", "\"Tree\""),
            GOOD.replace("\"}}", "\",}}"),
            GOOD.replace("\"entities\":{", "\"entities\":["),
            format!("{GOOD} "),
            GOOD.replace("}}", "},\"extra\":1}"),
            GOOD.replace("\"hash\"", "\"hush\""),
        ] {
            assert!(read(&bad).is_none(), "{bad}");
        }
    }
}
