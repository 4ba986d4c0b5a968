//! Rewriting a version-1 recording as version 2: the same lines (events, checkpoints, footer),
//! each checked with its version-1 checksum and signed again with the chained checksum, and the
//! header's `format_version` set to 2.

use std::io::{Read, Write};

use super::codec::sign_body;
use super::lines::Lines;
use super::{FORMAT_VERSION, Line, ReplayError, encode_line};

/// What [`upgrade`] wrote.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct UpgradeSummary {
    /// Lines written, the header included.
    pub lines: u64,
    /// Whether the input ended with a footer.
    pub complete: bool,
    /// Whether the input ended in a cut line (no newline), which is left out.
    pub cut: bool,
}

/// Reads a version-1 recording from `input`, checking every line as the replay does, and writes
/// it to `out` as version 2. `file` names the input in errors. A file that is already version 2
/// is refused.
pub fn upgrade<R: Read, W: Write>(input: R, file: &str, mut out: W) -> Result<UpgradeSummary, ReplayError> {
    let err = |(line, message): (Option<u64>, String)| ReplayError { file: file.to_string(), line, message };
    let mut lines = Lines::open(input).map_err(err)?;
    if lines.header.format_version >= FORMAT_VERSION {
        return Err(err((
            Some(1),
            format!("already format version {}; nothing to upgrade", lines.header.format_version),
        )));
    }
    let io = |e: std::io::Error| err((None, format!("cannot write the upgraded recording ({e})")));
    let mut header = lines.header.clone();
    header.format_version = FORMAT_VERSION;
    writeln!(out, "{}", encode_line(&Line::Header(header))).map_err(io)?;
    let mut summary = UpgradeSummary { lines: 1, complete: false, cut: false };
    // The chain starts after the header.
    let mut prev = 0;
    while let Some(checked) = lines.next().map_err(err)? {
        let (text, sum) = sign_body(&checked.body, prev);
        prev = sum;
        writeln!(out, "{text}").map_err(io)?;
        summary.lines += 1;
        summary.complete = matches!(checked.line, Line::Footer(_));
    }
    summary.cut = lines.cut;
    out.flush().map_err(io)?;
    Ok(summary)
}
