//! What `grove serve push` sends: a recording's lines read from its file as they are needed (a
//! last line cut short by a killed recorder is not sent, as the replay ignores it), and the time
//! each event line says it was made at, for pushing at the recording's own pace.

use std::collections::VecDeque;
use std::io::Read;
use std::path::Path;

use grove_systems::files::{self, Kind};
use grove_systems::limits::MAX_LINE_BYTES;

use crate::serve::client::conn::ClientError;
use crate::serve::line_split::LineSplitter;

/// The recording's lines, read as they are needed.
pub(super) struct Source {
    file: std::fs::File,
    splitter: LineSplitter,
    ready: VecDeque<String>,
    eof: bool,
    pub(super) name: String,
}

impl Source {
    pub(super) fn open(path: &Path) -> Result<Source, ClientError> {
        let (file, _) = files::open(path, Kind::Recording).map_err(|e| ClientError::Local(e.to_string()))?;
        Ok(Source { file, splitter: LineSplitter::new(MAX_LINE_BYTES), ready: VecDeque::new(), eof: false, name: path.display().to_string() })
    }

    pub(super) fn next(&mut self) -> Result<Option<String>, ClientError> {
        let mut chunk = vec![0u8; 64 * 1024];
        while self.ready.is_empty() && !self.eof {
            let n = self.file.read(&mut chunk).map_err(|e| ClientError::Local(format!("{}: {e}", self.name)))?;
            if n == 0 {
                self.eof = true;
                if !self.splitter.rest().is_empty() {
                    // A cut last line (a recorder killed mid-line) is not sent, as the replay ignores it.
                    break;
                }
            }
            let ready = &mut self.ready;
            self.splitter
                .push(&chunk[..n], &mut |l| {
                    ready.push_back(l);
                    true
                })
                .map_err(|e| ClientError::Local(format!("{}: {e}", self.name)))?;
        }
        Ok(self.ready.pop_front())
    }
}

/// The wall-clock milliseconds an event line was made at, if it says.
pub(super) fn event_ms(line: &str) -> Option<u64> {
    let v: serde_json::Value = serde_json::from_str(line).ok()?;
    v.get("ms")?.as_u64()
}
