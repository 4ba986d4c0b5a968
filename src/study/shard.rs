//! Shards of a study: a deterministic split of the recordings (or of the synthetic participants)
//! into N parts, and the partial result one part writes for `grove study merge`.
//!
//! A recording belongs to shard `xxh3_64(key) mod N + 1`, where the key is its file name up to
//! the first `-` (the participant, as `grove synth` names files: `P07-manual-7.jsonl` has the key
//! `P07`), or the whole file name when it has no `-`. The split depends only on the file names
//! and N, never on the machine, the folder's listing order or the thread count; a participant's
//! recordings stay together, so `grove synth --shard K/N` writes exactly the recordings that
//! `grove study --shard K/N` re-simulates. A
//! partial result holds the trials of its recordings for every run the study makes (the
//! baseline, the what-if, each value of a sweep) before they are ordered; the merge puts the
//! trials of every shard together, orders them as a run without shards does and writes the same
//! reports. `docs/scale.md` describes the file.

use std::path::{Path, PathBuf};

use grove_systems::set_arg::SetArg;
use serde::{Deserialize, Serialize};
use xxhash_rust::xxh3::xxh3_64;

use super::Trial;

/// The most shards a study can be split into.
pub const MAX_SHARDS: u32 = 1_000_000;
/// The first bytes of a partial result file.
pub const MAGIC: &[u8] = b"grove-study-part\n";
/// The version of the partial result encoding after [`MAGIC`].
pub const FORMAT: u32 = 1;

/// Why a partial result could not be written, read or merged.
#[derive(Debug, thiserror::Error)]
pub enum ShardError {
    /// The encoder failed.
    #[error("cannot encode the partial result: {0}")]
    Encode(postcard::Error),
    /// The file does not start as a partial result does.
    #[error("{0}: not a partial study result (write one with grove study --shard K/N --out FILE)")]
    NotAPartial(String),
    /// The file ends before its format version.
    #[error("{0}: the partial result is cut short")]
    CutShort(String),
    /// Another format version.
    #[error("{name}: partial result format {version}, this grove reads format {}", FORMAT)]
    Format {
        /// The file.
        name: String,
        /// Its version.
        version: u32,
    },
    /// The encoding does not decode, or decodes to what no shard writes.
    #[error("{name}: a damaged partial result ({reason})")]
    Damaged {
        /// The file.
        name: String,
        /// What is wrong.
        reason: String,
    },
    /// The file could not be read.
    #[error(transparent)]
    File(#[from] grove_systems::files::FileError),
    /// Nothing to merge.
    #[error("no partial results to merge")]
    NoParts,
    /// A part of another study.
    #[error("{name}: a shard of another study than {first} ({theirs}, not {ours})")]
    OtherStudy {
        /// The part.
        name: String,
        /// The first part.
        first: String,
        /// The part's study.
        theirs: String,
        /// The first part's study.
        ours: String,
    },
    /// A part of another split.
    #[error("{name}: shard {shard} of a split into {}, but {first} is of a split into {n}", shard.n)]
    OtherSplit {
        /// The part.
        name: String,
        /// Its shard.
        shard: Shard,
        /// The first part.
        first: String,
        /// The first part's number of shards.
        n: u32,
    },
    /// A part with another number of runs.
    #[error("{name}: {runs} runs, but {first} has {expected}")]
    RunCount {
        /// The part.
        name: String,
        /// Its runs.
        runs: usize,
        /// The first part.
        first: String,
        /// The first part's runs.
        expected: usize,
    },
    /// A shard given twice.
    #[error("shard {shard} is given twice: {first} and {second}")]
    GivenTwice {
        /// The shard.
        shard: Shard,
        /// The first file that holds it.
        first: String,
        /// The second.
        second: String,
    },
    /// A part holding a recording of another shard.
    #[error("{name}: holds {file}, which is in shard {home}, not {shard}")]
    Foreign {
        /// The part.
        name: String,
        /// The recording.
        file: String,
        /// The recording's shard.
        home: Shard,
        /// The part's shard.
        shard: Shard,
    },
    /// Shards missing (`shown`: the first few, with how many more).
    #[error("shard {shown} missing: {given} of {n} partial results given")]
    Missing {
        /// The missing shards, the first five and a count of the rest.
        shown: String,
        /// The parts given.
        given: usize,
        /// The number of shards.
        n: u32,
    },
}

/// One shard of N: `K/N` on the command line, 1 ≤ K ≤ N.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Shard {
    /// This shard, 1-based.
    pub k: u32,
    /// The number of shards.
    pub n: u32,
}

impl std::str::FromStr for Shard {
    type Err = String;
    fn from_str(s: &str) -> Result<Shard, String> {
        let bad = || format!("'{s}': expected K/N with 1 ≤ K ≤ N ≤ {MAX_SHARDS}, e.g. 3/8");
        let (k, n) = s.split_once('/').ok_or_else(bad)?;
        let (k, n): (u32, u32) = (k.trim().parse().map_err(|_| bad())?, n.trim().parse().map_err(|_| bad())?);
        if k == 0 || n == 0 || k > n || n > MAX_SHARDS {
            return Err(bad());
        }
        Ok(Shard { k, n })
    }
}

impl std::fmt::Display for StudyKey {
    /// The study's arguments as a command line writes them: `--set A=1 --set B=2,3 --baseline`
    /// (or "no --set" for a plain study).
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let mut words: Vec<String> = self.set.iter().map(|a| format!("--set {a}")).collect();
        if self.baseline {
            words.push("--baseline".into());
        }
        if words.is_empty() {
            words.push("no --set".into());
        }
        write!(f, "{}", words.join(" "))
    }
}

impl std::fmt::Display for Shard {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}", self.k, self.n)
    }
}

impl Shard {
    /// Whether the recording (or participant) with this file name (or id) is in this shard.
    pub fn holds(&self, file_name: &str) -> bool {
        shard_of(file_name, self.n) == self.k
    }

    /// The files of `files` in this shard, in their order.
    pub fn files(&self, files: &[PathBuf]) -> Vec<PathBuf> {
        files.iter().filter(|f| self.holds(&file_name(f))).cloned().collect()
    }
}

/// What a file name is sharded by: the part before the first `-`, or the whole name.
pub fn shard_key(file_name: &str) -> &str {
    file_name.split_once('-').map_or(file_name, |(p, _)| p)
}

/// The shard (1-based) among `n` of the recording with this file name.
pub fn shard_of(file_name: &str, n: u32) -> u32 {
    (xxh3_64(shard_key(file_name).as_bytes()) % n as u64) as u32 + 1
}

fn file_name(path: &Path) -> String {
    path.file_name().map(|f| f.to_string_lossy().into_owned()).unwrap_or_default()
}

/// What the study was: every shard of one study has the same key, and the merge checks it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StudyKey {
    /// The `--set` arguments, each checked again when a partial result is read.
    pub set: Vec<SetArg>,
    /// Whether the what-if compares with `--baseline` recordings (re-simulated participants).
    pub baseline: bool,
}

/// The trials of one run of a study (the baseline, the what-if, one value of a sweep) for the
/// recordings of one shard, and the seconds they took.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct RunPart {
    /// The trials, in any order.
    pub trials: Vec<Trial>,
    /// Wall-clock seconds of this shard's re-simulations.
    pub wall_seconds: f64,
}

/// The partial result of one shard.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Partial {
    /// Which shard.
    pub shard: Shard,
    /// Which study.
    pub study: StudyKey,
    /// The `--replays` folder as this shard was given it (for messages).
    pub replays: String,
    /// The runs, in the order the study makes them (see `cli::study::compute`).
    pub runs: Vec<RunPart>,
}

impl Partial {
    /// The bytes of the file: [`MAGIC`], the format version (u32, little-endian) and the
    /// postcard encoding of the partial (floats as their exact bits, so a merge reproduces
    /// every value of a run without shards).
    pub fn encode(&self) -> Result<Vec<u8>, ShardError> {
        let mut bytes = MAGIC.to_vec();
        bytes.extend_from_slice(&FORMAT.to_le_bytes());
        postcard::to_extend(self, bytes).map_err(ShardError::Encode)
    }

    /// Reads the bytes [`Partial::encode`] wrote. `name` is the file, for messages.
    pub fn decode(bytes: &[u8], name: &str) -> Result<Partial, ShardError> {
        let rest = bytes.strip_prefix(MAGIC).ok_or_else(|| ShardError::NotAPartial(name.to_string()))?;
        let (version, body) = rest.split_first_chunk::<4>().ok_or_else(|| ShardError::CutShort(name.to_string()))?;
        let version = u32::from_le_bytes(*version);
        if version != FORMAT {
            return Err(ShardError::Format { name: name.to_string(), version });
        }
        let damaged = |reason: String| ShardError::Damaged { name: name.to_string(), reason };
        let (part, left): (Partial, &[u8]) = postcard::take_from_bytes(body).map_err(|e| damaged(e.to_string()))?;
        if !left.is_empty() {
            return Err(damaged(format!("{} bytes after its end", left.len())));
        }
        let Shard { k, n } = part.shard;
        if k == 0 || k > n || n > MAX_SHARDS {
            return Err(damaged(format!("shard {k}/{n}")));
        }
        Ok(part)
    }

    /// Reads a partial result file.
    pub fn read(path: &Path) -> Result<Partial, ShardError> {
        let bytes = grove_systems::files::read(path, grove_systems::files::Kind::Cache)?;
        Partial::decode(&bytes, &path.display().to_string())
    }
}

/// Checks that `parts` are every shard of one study, each once, and puts their runs together:
/// one list of trials and the summed seconds per run, with the study's key and the first
/// shard's `--replays` folder. `names` are the files, for messages.
pub fn combine(parts: Vec<Partial>, names: &[String]) -> Result<(StudyKey, String, Vec<RunPart>), ShardError> {
    let Some(first) = parts.first() else { return Err(ShardError::NoParts) };
    let (n, study, runs, replays) = (first.shard.n, first.study.clone(), first.runs.len(), first.replays.clone());
    let mut seen: Vec<Option<&str>> = vec![None; n as usize];
    for (p, name) in parts.iter().zip(names) {
        if p.study != study {
            return Err(ShardError::OtherStudy {
                name: name.clone(),
                first: names[0].clone(),
                theirs: p.study.to_string(),
                ours: study.to_string(),
            });
        }
        if p.shard.n != n {
            return Err(ShardError::OtherSplit { name: name.clone(), shard: p.shard, first: names[0].clone(), n });
        }
        if p.runs.len() != runs {
            return Err(ShardError::RunCount {
                name: name.clone(),
                runs: p.runs.len(),
                first: names[0].clone(),
                expected: runs,
            });
        }
        let slot = &mut seen[p.shard.k as usize - 1];
        if let Some(other) = slot {
            return Err(ShardError::GivenTwice { shard: p.shard, first: other.to_string(), second: name.clone() });
        }
        *slot = Some(name);
        if let Some(t) = p.runs.iter().flat_map(|r| &r.trials).find(|t| !p.shard.holds(&t.file)) {
            return Err(ShardError::Foreign {
                name: name.clone(),
                file: t.file.clone(),
                home: Shard { k: shard_of(&t.file, n), n },
                shard: p.shard,
            });
        }
    }
    let missing: Vec<String> =
        seen.iter().enumerate().filter(|(_, s)| s.is_none()).map(|(i, _)| format!("{}/{n}", i + 1)).collect();
    if !missing.is_empty() {
        let shown = missing.iter().take(5).cloned().collect::<Vec<_>>().join(", ");
        let more = if missing.len() > 5 { format!(" and {} more", missing.len() - 5) } else { String::new() };
        return Err(ShardError::Missing { shown: format!("{shown}{more}"), given: parts.len(), n });
    }
    let mut merged: Vec<RunPart> = (0..runs).map(|_| RunPart { trials: Vec::new(), wall_seconds: 0.0 }).collect();
    for p in parts {
        for (m, r) in merged.iter_mut().zip(p.runs) {
            m.trials.extend(r.trials);
            m.wall_seconds += r.wall_seconds;
        }
    }
    Ok((study, replays, merged))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shards_parse_and_refuse_what_is_not_k_of_n() {
        assert_eq!("3/8".parse::<Shard>(), Ok(Shard { k: 3, n: 8 }));
        for bad in ["0/4", "5/4", "1/0", "4", "a/b", "1/2/3", "-1/4", "1/2000000"] {
            assert!(bad.parse::<Shard>().is_err(), "{bad}");
        }
    }

    #[test]
    fn a_participants_recordings_share_a_shard() {
        assert_eq!(shard_key("P07-manual-7.jsonl"), "P07");
        assert_eq!(shard_key("alice.jsonl"), "alice.jsonl");
        for n in [2, 3, 5, 8] {
            for p in 1..=50 {
                assert_eq!(
                    shard_of(&format!("P{p:02}-manual-7.jsonl"), n),
                    shard_of(&format!("P{p:02}-ray-casting-7.jsonl"), n)
                );
                assert_eq!(shard_of(&format!("P{p:02}-manual-7.jsonl"), n), shard_of(&format!("P{p:02}"), n));
            }
        }
    }

    #[test]
    fn every_name_is_in_exactly_one_shard_and_the_split_is_fixed() {
        let names: Vec<String> = (1..=200).map(|i| format!("P{i:02}-manual-7.jsonl")).collect();
        for n in [1, 2, 3, 7] {
            for name in &names {
                let holders = (1..=n).filter(|&k| Shard { k, n }.holds(name)).count();
                assert_eq!(holders, 1, "{name} in {holders} of {n} shards");
            }
        }
        // The split is XXH3 of the name: pinned to the hash, not to this machine.
        assert_eq!(shard_of("P01-manual-7.jsonl", 4) as u64, xxh3_64(b"P01") % 4 + 1);
        // Four shards of 200 names are each far from empty.
        for k in 1..=4 {
            let c = names.iter().filter(|n| Shard { k, n: 4 }.holds(n)).count();
            assert!(c > 25, "shard {k}/4 holds {c} of 200");
        }
    }

    fn part(k: u32, n: u32) -> Partial {
        let study = StudyKey { set: vec![], baseline: false };
        Partial {
            shard: Shard { k, n },
            study,
            replays: "r".into(),
            runs: vec![RunPart { trials: vec![], wall_seconds: 0.25 }],
        }
    }

    #[test]
    fn a_partial_round_trips_and_damage_is_refused() {
        let bytes = part(2, 3).encode().unwrap();
        let back = Partial::decode(&bytes, "p").unwrap();
        assert_eq!(back.shard, Shard { k: 2, n: 3 });
        assert_eq!(back.runs[0].wall_seconds, 0.25);
        assert!(Partial::decode(&bytes[..bytes.len() - 1], "p").is_err());
        assert!(Partial::decode(b"{\"json\": 1}", "p").is_err());
        let mut longer = bytes.clone();
        longer.push(0);
        assert!(Partial::decode(&longer, "p").unwrap_err().to_string().contains("after its end"));
        for (k, n) in [(0, 3), (4, 3), (1, MAX_SHARDS + 1)] {
            let bad = Partial { shard: Shard { k, n }, ..part(1, 3) }.encode().unwrap();
            assert!(Partial::decode(&bad, "p").unwrap_err().to_string().contains("damaged"), "{k}/{n}");
        }
        let mut other = bytes;
        other[MAGIC.len()] = 9;
        assert!(Partial::decode(&other, "p").unwrap_err().to_string().contains("format 9"));
    }

    #[test]
    fn the_study_key_is_typed_and_encoded_as_the_text_it_was() {
        let set: Vec<SetArg> = vec!["snap_threshold= 0.2".parse().unwrap(), "spawn_drop=0.1,0.3".parse().unwrap()];
        // Each argument is encoded as its text, as format 1 wrote the arguments.
        assert_eq!(postcard::to_allocvec(&set[0]).unwrap(), postcard::to_allocvec("snap_threshold=0.2").unwrap());
        let mut p = part(1, 2);
        p.study = StudyKey { set, baseline: true };
        let back = Partial::decode(&p.encode().unwrap(), "p").unwrap();
        assert_eq!(back.study, p.study);
        assert_eq!(back.study.to_string(), "--set snap_threshold=0.2 --set spawn_drop=0.1,0.3 --baseline");
        // A part whose arguments do not hold is damaged; one that holds reads as written.
        let mut bytes = MAGIC.to_vec();
        bytes.extend_from_slice(&FORMAT.to_le_bytes());
        let foreign = (
            Shard { k: 1, n: 1 },
            (vec!["snap_threshold=99".to_string()], false),
            "r".to_string(),
            Vec::<RunPart>::new(),
        );
        let bytes = postcard::to_extend(&foreign, bytes).unwrap();
        let e = Partial::decode(&bytes, "p").unwrap_err().to_string();
        assert!(e.contains("damaged partial result"), "{e}");
        let fine = (
            Shard { k: 1, n: 1 },
            (vec!["snap_threshold=9".to_string()], false),
            "r".to_string(),
            Vec::<RunPart>::new(),
        );
        let mut bytes = MAGIC.to_vec();
        bytes.extend_from_slice(&FORMAT.to_le_bytes());
        assert_eq!(
            Partial::decode(&postcard::to_extend(&fine, bytes).unwrap(), "p").unwrap().study.set[0].values[0].value,
            9.0
        );
        let e = combine(vec![part(1, 2), p], &["a".into(), "b".into()]).unwrap_err().to_string();
        assert!(e.contains("b: a shard of another study than a (--set snap_threshold=0.2 --set spawn_drop=0.1,0.3 --baseline, not no --set)"), "{e}");
    }

    #[test]
    fn a_missing_or_repeated_shard_is_refused() {
        let names: Vec<String> = ["a", "b", "c"].iter().map(|s| s.to_string()).collect();
        let e = combine(vec![part(1, 3), part(3, 3)], &names).unwrap_err().to_string();
        assert!(e.contains("shard 2/3 missing"), "{e}");
        let e = combine(vec![part(1, 3), part(2, 3), part(2, 3)], &names).unwrap_err().to_string();
        assert!(e.contains("shard 2/3 is given twice: b and c"), "{e}");
        let e = combine(vec![part(1, 3), part(2, 2)], &names).unwrap_err().to_string();
        assert!(e.contains("split into 2"), "{e}");
        let (_, _, runs) = combine(vec![part(2, 3), part(1, 3), part(3, 3)], &names).unwrap();
        assert_eq!(runs[0].wall_seconds, 0.75);
        // A trial of another shard: the partial is not what it says.
        let trial = crate::study::evaluate(Path::new("no-such-folder/P05-manual-7.jsonl"), &[]);
        let home = shard_of(&trial.file, 3);
        let mut wrong = part(home % 3 + 1, 3);
        wrong.runs[0].trials.push(trial);
        let mut parts: Vec<Partial> = (1..=3).filter(|&k| k != home % 3 + 1).map(|k| part(k, 3)).collect();
        parts.push(wrong);
        let e = combine(parts, &names).unwrap_err().to_string();
        assert!(e.contains(&format!("P05-manual-7.jsonl, which is in shard {home}/3")), "{e}");
    }
}
