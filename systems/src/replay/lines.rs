//! The checked stream of a recording's lines: bounded line length, the header first, checksums
//! (chained from version 2 on), and the structural rules every line must keep, whatever the
//! simulation does with it.
//!
//! The rules are [`super::line_rules`]'s, checked before any simulation: the header comes first
//! and only once; nothing follows the footer; ticks never decrease; no tick is past the tick
//! limit; and no line is more than a checkpoint interval past the last checkpoint (or the
//! start), since the recorder writes one every interval. The last rule bounds the simulation a
//! file can ask for by its number of lines.

use std::io::{BufRead, BufReader, Read};

use super::codec::Maps;
use super::line_rules::{header_line, LineRules, RuledLine};
use super::{Header, Line, MAX_LINE};

/// A problem at a line (1-based; `None` for the file as a whole), as the caller reports it.
pub(crate) type LineError = (Option<u64>, String);

/// Reads lines with a length limit, never holding more than one line in memory.
struct LineReader<R: Read> {
    inner: BufReader<R>,
    buf: Vec<u8>,
    /// A line's buffer given back (see [`Lines::keep_checkpoint_bodies_only`]), which the next
    /// line is read into instead of a new allocation.
    spare: Vec<u8>,
    number: u64,
}

enum NextLine {
    Line(String),
    /// The file ended with bytes that have no newline: a line cut by a killed writer.
    Cut,
    End,
}

impl<R: Read> LineReader<R> {
    fn next(&mut self) -> Result<NextLine, String> {
        self.number += 1;
        // Most lines lie whole in the reader's buffer: taken from it directly, in one allocation.
        if let Ok(available) = self.inner.fill_buf()
            && let Some(end) = memchr::memchr(b'\n', available).filter(|&end| end <= MAX_LINE)
        {
            let mut line = std::mem::take(&mut self.spare);
            line.clear();
            line.extend_from_slice(&available[..end]);
            self.inner.consume(end + 1);
            return String::from_utf8(line).map(NextLine::Line).map_err(|_| "not valid UTF-8 text".into());
        }
        self.buf.clear();
        // At most one byte past the limit is read, so a line without an end never fills memory.
        let limit = MAX_LINE as u64 + 1;
        (&mut self.inner).take(limit).read_until(b'\n', &mut self.buf).map_err(|e| e.to_string())?;
        if self.buf.last() == Some(&b'\n') {
            self.buf.pop();
        } else if self.buf.len() > MAX_LINE {
            return Err(format!("line longer than the limit of {MAX_LINE} bytes; not a grove recording"));
        } else {
            return Ok(if self.buf.is_empty() { NextLine::End } else { NextLine::Cut });
        }
        // The next line's buffer starts at this one's size, so reading it allocates once.
        let next = Vec::with_capacity(self.buf.len() + 32);
        let line = std::mem::replace(&mut self.buf, next);
        String::from_utf8(line).map(NextLine::Line).map_err(|_| "not valid UTF-8 text".into())
    }
}

/// One checked line after the header.
pub(crate) struct Checked {
    /// Its 1-based line number.
    pub number: u64,
    /// The parsed line.
    pub line: Line,
    /// Its tick (an event's or checkpoint's `tick`, the footer's `final_tick`).
    pub tick: u64,
    /// Its text without the `sum` field (empty for a line other than a checkpoint after
    /// [`Lines::keep_checkpoint_bodies_only`]).
    pub body: String,
}

/// A checkpoint line's body (its text without the `sum` field) read with all its maps; `None`
/// for another line.
pub(crate) fn checkpoint_of(body: &str) -> Option<super::CheckpointLine> {
    match super::codec::parse_body(body, Maps::Read) {
        Ok(Line::Checkpoint(c)) => Some(c),
        _ => None,
    }
}

/// A recording's lines, checked one at a time by the format's [`LineRules`].
pub(crate) struct Lines<R: Read> {
    reader: LineReader<R>,
    /// The header (read by [`Lines::open`]).
    pub header: Header,
    rules: LineRules,
    /// Whether the file ended in a line without a newline (a cut line, ignored).
    pub cut: bool,
    /// Whether only checkpoints keep their body (see [`Lines::keep_checkpoint_bodies_only`]).
    checkpoint_bodies_only: bool,
}

impl<R: Read> Lines<R> {
    /// Reads and checks the header.
    pub fn open(reader: R) -> Result<Lines<R>, LineError> {
        let mut reader = LineReader { inner: BufReader::with_capacity(64 * 1024, reader), buf: Vec::new(), spare: Vec::new(), number: 0 };
        let first = match reader.next().map_err(|m| (Some(1), m))? {
            NextLine::End => return Err((None, "empty file; expected a grove recording header".into())),
            NextLine::Cut => return Err((Some(1), "the header line is cut off (no newline)".into())),
            NextLine::Line(l) => l,
        };
        let header = header_line(&first).map_err(|m| (Some(1), m.0))?;
        let rules = LineRules::after(&header);
        Ok(Lines { reader, header, rules, cut: false, checkpoint_bodies_only: false })
    }

    /// From now on, a checkpoint's `components` and `entities` maps are checked to be maps of
    /// strings but left empty: for a reader that needs them only at a divergence, and then reads
    /// them from the line's body ([`checkpoint_of`]).
    pub fn checkpoint_maps_when_needed(&mut self) {
        self.rules.checkpoint_maps_when_needed();
    }

    /// From now on, only a checkpoint's [`Checked::body`] is kept, any other line's is empty:
    /// for a reader that reads no other line's text again. Its buffer is then reused for the
    /// next line.
    pub fn keep_checkpoint_bodies_only(&mut self) {
        self.checkpoint_bodies_only = true;
    }

    /// The next checked line, or `None` at the end of the file (or at a cut last line).
    pub fn next(&mut self) -> Result<Option<Checked>, LineError> {
        let n = self.reader.number + 1;
        let text = match self.reader.next().map_err(|m| (Some(n), m))? {
            NextLine::End => return Ok(None),
            NextLine::Cut => {
                self.cut = true;
                return Ok(None);
            }
            NextLine::Line(l) => l,
        };
        let RuledLine { line, tick, body } = self.rules.check(text).map_err(|m| (Some(n), m.0))?;
        let body = if self.checkpoint_bodies_only && !matches!(line, Line::Checkpoint(_)) {
            self.reader.spare = body.into_bytes();
            String::new()
        } else {
            body
        };
        Ok(Some(Checked { number: n, line, tick, body }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read_all(bytes: &[u8]) -> Vec<Result<String, String>> {
        let mut r = LineReader { inner: BufReader::with_capacity(64, bytes), buf: Vec::new(), spare: Vec::new(), number: 0 };
        let mut out = Vec::new();
        loop {
            match r.next() {
                Ok(NextLine::Line(l)) => out.push(Ok(l)),
                Ok(NextLine::Cut) => out.push(Ok("<cut>".into())),
                Ok(NextLine::End) => return out,
                Err(e) => {
                    out.push(Err(e));
                    return out;
                }
            }
        }
    }

    #[test]
    fn with_checkpoint_bodies_only_the_same_lines_are_read_and_only_checkpoints_keep_their_text() {
        let file = include_bytes!("../../../replays/scenarios/plant-two.jsonl");
        let read = |only: bool| {
            let mut lines = Lines::open(&file[..]).unwrap();
            if only {
                lines.keep_checkpoint_bodies_only();
            }
            std::iter::from_fn(|| lines.next().unwrap()).map(|c| (c.number, c.tick, format!("{:?}", c.line), c.body)).collect::<Vec<_>>()
        };
        let (all, only) = (read(false), read(true));
        assert_eq!(all.len(), only.len());
        let mut checkpoints = 0;
        for (a, o) in all.iter().zip(&only) {
            assert_eq!((a.0, a.1, &a.2), (o.0, o.1, &o.2));
            if a.2.starts_with("Checkpoint") {
                checkpoints += 1;
                assert_eq!(a.3, o.3);
            } else {
                assert!(!a.3.is_empty() && o.3.is_empty(), "{}", a.3);
            }
        }
        assert!(checkpoints > 0 && checkpoints < all.len());
    }

    #[test]
    fn lines_up_to_the_limit_are_read_and_longer_ones_refused() {
        let at = "a".repeat(MAX_LINE);
        let over = "b".repeat(MAX_LINE + 1);
        let text = format!("one\n\n{at}\ntwo\n{over}\nthree\n");
        let got = read_all(text.as_bytes());
        assert_eq!(got.len(), 5);
        assert_eq!(got[..4], [Ok("one".to_string()), Ok(String::new()), Ok(at), Ok("two".to_string())]);
        assert!(got[4].as_ref().is_err_and(|e| e.contains("longer than the limit")), "{:?}", got[4].as_ref().map(|s| s.len()));
        // The same without a newline at all: refused, not held whole.
        assert!(read_all(over.as_bytes())[0].is_err());
        // A last line without its newline is a cut line; invalid UTF-8 is refused.
        assert_eq!(read_all(b"x\ny"), [Ok("x".to_string()), Ok("<cut>".to_string())]);
        assert!(read_all(b"\xff\xfe\n")[0].is_err());
    }
}
