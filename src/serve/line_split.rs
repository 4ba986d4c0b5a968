//! Lines out of a stream of byte chunks (a request body, a file read in pieces), each at most a
//! limit long, never holding more than one line and one chunk: a line without its end that
//! grows past the limit is refused as soon as it does, not read to its end.

/// Why a line was not taken.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum SplitError {
    /// The line grew past the limit before its newline came.
    #[error("line {number} is longer than the limit of {limit} bytes")]
    TooLong {
        /// Its 1-based number in the stream.
        number: u64,
        /// The limit, bytes.
        limit: usize,
    },
    /// The line is not UTF-8 text.
    #[error("line {number} is not valid UTF-8 text")]
    NotUtf8 {
        /// Its 1-based number in the stream.
        number: u64,
    },
}

/// Splits chunks into lines (without their `\n`).
pub struct LineSplitter {
    pending: Vec<u8>,
    limit: usize,
    /// Lines returned so far.
    number: u64,
    failed: bool,
}

impl LineSplitter {
    /// A splitter for lines of at most `limit` bytes (the newline not counted).
    pub fn new(limit: usize) -> LineSplitter {
        LineSplitter { pending: Vec::new(), limit, number: 0, failed: false }
    }

    /// Feeds a chunk; calls `line` with each complete line in order, stopping at the first line
    /// `line` refuses (returns `false` for) or that is too long or not UTF-8 (then returned as the
    /// error, and the splitter takes nothing more).
    pub fn push(&mut self, mut chunk: &[u8], line: &mut dyn FnMut(String) -> bool) -> Result<bool, SplitError> {
        while !self.failed && !chunk.is_empty() {
            match chunk.iter().position(|&b| b == b'\n') {
                Some(end) => {
                    if self.pending.len() + end > self.limit {
                        return Err(self.fail_long());
                    }
                    self.pending.extend_from_slice(&chunk[..end]);
                    chunk = &chunk[end + 1..];
                    self.number += 1;
                    let bytes = std::mem::take(&mut self.pending);
                    let text = String::from_utf8(bytes).map_err(|_| {
                        self.failed = true;
                        SplitError::NotUtf8 { number: self.number }
                    })?;
                    if !line(text) {
                        self.failed = true;
                        return Ok(false);
                    }
                }
                None => {
                    if self.pending.len() + chunk.len() > self.limit {
                        return Err(self.fail_long());
                    }
                    self.pending.extend_from_slice(chunk);
                    chunk = &[];
                }
            }
        }
        Ok(!self.failed)
    }

    fn fail_long(&mut self) -> SplitError {
        self.failed = true;
        self.pending = Vec::new();
        SplitError::TooLong { number: self.number + 1, limit: self.limit }
    }

    /// The bytes after the last newline (a cut last line), if any.
    pub fn rest(&self) -> &[u8] {
        &self.pending
    }

    /// How many lines were taken.
    pub fn lines(&self) -> u64 {
        self.number
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn split(chunks: &[&[u8]], limit: usize) -> (Vec<String>, Result<bool, SplitError>, Vec<u8>) {
        let mut s = LineSplitter::new(limit);
        let mut out = Vec::new();
        let mut last = Ok(true);
        for c in chunks {
            last = s.push(c, &mut |l| {
                out.push(l);
                true
            });
            if !matches!(last, Ok(true)) {
                break;
            }
        }
        (out, last, s.rest().to_vec())
    }

    #[test]
    fn lines_across_chunks_come_out_whole() {
        let (lines, r, rest) = split(&[b"ab", b"c\nde\n\nf", b"g\nh"], 8);
        assert_eq!(lines, ["abc", "de", "", "fg"]);
        assert_eq!(r, Ok(true));
        assert_eq!(rest, b"h");
    }

    #[test]
    fn a_line_past_the_limit_is_refused_before_its_end_arrives() {
        let (lines, r, _) = split(&[b"12345678\n123", b"456789"], 8);
        assert_eq!(lines, ["12345678"]);
        assert_eq!(r, Err(SplitError::TooLong { number: 2, limit: 8 }));
        let (_, r, _) = split(&[b"123456789\n"], 8);
        assert_eq!(r, Err(SplitError::TooLong { number: 1, limit: 8 }));
        let (lines, r, _) = split(&[b"ok\n\xff\xfe\nafter\n"], 8);
        assert_eq!((lines, r), (vec!["ok".to_string()], Err(SplitError::NotUtf8 { number: 2 })));
    }

    #[test]
    fn a_refused_line_stops_the_split() {
        let mut s = LineSplitter::new(8);
        let mut seen = Vec::new();
        let r = s.push(b"a\nb\nc\n", &mut |l| {
            seen.push(l.clone());
            l != "b"
        });
        assert_eq!((r, seen), (Ok(false), vec!["a".to_string(), "b".to_string()]));
        assert_eq!(s.push(b"d\n", &mut |_| true), Ok(false));
    }
}
