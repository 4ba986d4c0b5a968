//! The study library's errors: reading the recordings' folder and writing the reports
//! ([`StudyError`]) and the synthetic participants ([`SynthError`]); the partial results of
//! shards have theirs in [`super::shard`]. Each message is one line that names the file or folder.

use std::path::PathBuf;

use grove_systems::resources::ConfigError;

use crate::atomic_write::WriteError;

use super::shard::ShardError;

/// Why a study could not read its recordings or write its reports.
#[derive(Debug, thiserror::Error)]
pub enum StudyError {
    /// The recordings' folder does not exist.
    #[error("{}: no such folder", .0.display())]
    NoSuchFolder(PathBuf),
    /// The recordings' folder is a file.
    #[error("{}: is not a folder of recordings", .0.display())]
    NotAFolder(PathBuf),
    /// The folder holds no `*.jsonl` file.
    #[error("{}: no recordings (*.jsonl) in this folder", .0.display())]
    NoRecordings(PathBuf),
    /// A folder could not be listed or made.
    #[error("{}: {source}", path.display())]
    Folder {
        /// The folder.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// The reports' folder is a file.
    #[error("{}: exists and is not a folder", .0.display())]
    OutIsAFile(PathBuf),
    /// The reports' folder holds the reports of an earlier run.
    #[error("{}: holds the reports of an earlier run ({}); use --force to replace them, or another --out", out.display(), old.display())]
    EarlierReports {
        /// The folder.
        out: PathBuf,
        /// The first report found there.
        old: PathBuf,
    },
    /// A CSV report could not be written.
    #[error("{}: {source}", path.display())]
    Csv {
        /// The file.
        path: PathBuf,
        /// Why.
        source: csv::Error,
    },
    /// A chart could not be drawn (`what`: its file, or "SVG chart").
    #[error("{what}: {reason}")]
    Chart {
        /// The file or the kind of chart.
        what: String,
        /// The drawing backend's message.
        reason: String,
    },
    /// A protocol folder's questionnaire answers or protocol could not be read.
    #[error("{path}: {reason}")]
    Answers {
        /// The file.
        path: String,
        /// Why, one line.
        reason: String,
    },
    /// A value could not be written as JSON.
    #[error("cannot write JSON: {0}")]
    Json(#[from] serde_json::Error),
    /// A report could not be put in place.
    #[error(transparent)]
    Write(#[from] WriteError),
    /// What-if recordings (`--baseline`) without a changed setting in their headers.
    #[error(
        "{0}: the recordings carry no changed setting (`config` in their headers); write them with `grove synth --set NAME=VALUE`"
    )]
    NoChangedSetting(String),
    /// The settings of what-if recordings do not hold together.
    #[error("{replays}: {source}")]
    Settings {
        /// The `--replays` folder.
        replays: String,
        /// Why.
        source: ConfigError,
    },
    /// Runs that do not fit the study (a merge of parts that do not hold what they say).
    #[error("a study of {expected} runs given {given}")]
    Runs {
        /// The runs the study makes.
        expected: usize,
        /// The runs given.
        given: usize,
    },
    /// A recording could not be checked.
    #[error(transparent)]
    Systems(#[from] grove_systems::Error),
    /// [`ShardError`].
    #[error(transparent)]
    Shard(#[from] ShardError),
    /// [`SynthError`].
    #[error(transparent)]
    Synth(#[from] SynthError),
}

/// Why synthetic recordings could not be made.
#[derive(Debug, thiserror::Error)]
pub enum SynthError {
    /// A participant could not do what the task asks (without a what-if setting, a fault).
    #[error("{0}")]
    Participant(String),
    /// A participant did not complete the task.
    #[error("participant {participant} did not complete task {task}")]
    Incomplete {
        /// The participant, 1-based.
        participant: usize,
        /// The task.
        task: String,
    },
    /// A task names a scene that is not built in.
    #[error("task {task} names unknown scene '{scene}'")]
    UnknownScene {
        /// The task.
        task: String,
        /// The scene.
        scene: String,
    },
    /// A built-in task is missing.
    #[error("built-in task {0} is missing")]
    MissingTask(String),
    /// A target's model is not in the catalogue.
    #[error("target {0} has an unknown model")]
    UnknownModel(usize),
    /// `--techniques` names a technique that is not registered.
    #[error("--techniques: {0}")]
    UnknownTechnique(String),
    /// `--techniques` names a technique twice.
    #[error("--techniques names '{0}' twice")]
    TechniqueTwice(String),
    /// The output folder is a file.
    #[error("{}: exists and is not a folder", .0.display())]
    OutIsAFile(PathBuf),
    /// A recording exists and `force` is off.
    #[error("{}: already exists; use --force to overwrite the recordings in {}", file.display(), out.display())]
    Exists {
        /// The recording.
        file: PathBuf,
        /// The folder.
        out: PathBuf,
    },
    /// A file or folder could not be written.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file or folder.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// The settings do not hold together.
    #[error("--set {0}")]
    Settings(ConfigError),
    /// A session could not be recorded.
    #[error("{}: {source}", path.display())]
    Record {
        /// The recording.
        path: PathBuf,
        /// Why.
        source: grove_systems::replay::RecordError,
    },
    /// The simulation refused the session's scene.
    #[error(transparent)]
    Systems(#[from] grove_systems::Error),
}
