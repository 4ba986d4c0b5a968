//! Fuzz target: any bytes as a recording. The reader must return (an error or an outcome) and
//! never panic; the tick and line limits keep each input's work bounded. The recording's folder
//! is the fuzzer's working directory, so a header may name only a built-in scene or a `.ron` file
//! there.

#![no_main]

use grove_systems::replay::{replay_reader, ReplayOptions};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    // Stop early so each input stays fast: the limits are tested elsewhere, panics are the goal.
    let options = ReplayOptions { until: Some(600), ..Default::default() };
    let _ = replay_reader(data, "fuzz.jsonl", None, &options);
});
