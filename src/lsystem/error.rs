//! [`LsystemError`]: why a grammar could not be read or compiled, a string not derived or
//! interpreted, or a model not built or written. Its `Display` is one line, worded as the CLI
//! prints it; the errors it wraps are shown in that line rather than as a `source()`, since the
//! CLI prints an error's whole chain.

use std::path::PathBuf;

use super::expr::ExprError;

/// The grammar file's keys, as an unknown key's message lists them.
const KEYS: &str = "name, axiom, rule, angle, step, width, width-factor, species, height, n";

/// Why an L-system operation failed.
#[derive(Debug, thiserror::Error)]
pub enum LsystemError {
    /// An error in a named part of a grammar: `at` is how the message names it ("axiom",
    /// "rule 2 'F -> FF'", "tree.txt line 3", the grammar file).
    #[error("{at}: {error}")]
    At {
        /// The part, as the message names it.
        at: String,
        /// What is wrong there.
        error: Box<LsystemError>,
    },
    /// A parameter list that follows no symbol (its column, from 1).
    #[error("'(' at column {0} follows no symbol")]
    ParenAfterNothing(usize),
    /// Parameters given to a bracket.
    #[error("'{0}' takes no parameters")]
    BracketParameters(char),
    /// A symbol's second parameter list (its column).
    #[error("a second parameter list at column {0}")]
    SecondParameterList(usize),
    /// A parameter list that is never closed (its column).
    #[error("'(' at column {0} is never closed")]
    Unclosed(usize),
    /// An empty parameter (the column of its list).
    #[error("an empty parameter at column {0}")]
    EmptyParameter(usize),
    /// A character that is no symbol.
    #[error("'{ch}' at column {column} is neither a letter nor a turtle command (+ - & ^ \\ / | [ ] !)")]
    NotSymbol {
        /// The character.
        ch: char,
        /// Its column, from 1.
        column: usize,
    },
    /// A `]` without its `[` in an axiom or successor.
    #[error("']' without a matching '['")]
    UnmatchedClose,
    /// `[` without their `]` in an axiom or successor (how many).
    #[error("{0} '[' without a matching ']'")]
    UnmatchedOpen(i64),
    /// A symbol with more than 8 parameters.
    #[error("'{sym}' has {n} parameters, at most 8 are allowed")]
    TooManyParameters {
        /// The symbol.
        sym: char,
        /// Its parameters.
        n: usize,
    },
    /// A symbol with another number of parameters than elsewhere in the grammar.
    #[error("'{sym}' has {n} parameters here but {elsewhere} elsewhere")]
    Arity {
        /// The symbol.
        sym: char,
        /// Its parameters here.
        n: usize,
        /// Its parameters elsewhere.
        elsewhere: u8,
    },
    /// The turtle's angle, step or width out of range.
    #[error("angle must be finite, step positive and width not negative")]
    Turtle,
    /// A width factor that is not positive.
    #[error("width-factor must be positive")]
    WidthFactor,
    /// A grammar's height that is not positive.
    #[error("height must be a positive number of metres")]
    Height,
    /// A species grove has no materials for.
    #[error("species '{name}' is not one of {known}")]
    Species {
        /// The species named.
        name: String,
        /// The species grove knows, listed.
        known: String,
    },
    /// An empty axiom.
    #[error("the axiom is empty")]
    EmptyAxiom,
    /// A parameter expression that does not parse.
    #[error("{0}")]
    Expr(ExprError),
    /// A rule without an arrow.
    #[error("no '->' (or '=') between predecessor and successor")]
    NoArrow,
    /// A stochastic weight that does not parse.
    #[error("the weight '{0}' is not a number")]
    WeightNotNumber(String),
    /// A stochastic weight that is negative or not finite.
    #[error("the weight must be a finite number, not negative")]
    Weight,
    /// A predecessor of more or less than one symbol.
    #[error("the predecessor must be exactly one symbol")]
    Predecessor,
    /// A rule for a bracket.
    #[error("brackets cannot be rewritten")]
    RewriteBracket,
    /// A predecessor's parameter that is not a name.
    #[error("the predecessor's parameter '{0}' is not a name")]
    ParameterNotName(String),
    /// A predecessor's parameter named twice.
    #[error("the parameter name '{0}' appears twice")]
    ParameterTwice(String),
    /// Stochastic weights on conditional rules (the symbol).
    #[error("rules for '{0}': a stochastic weight cannot be combined with conditions")]
    WeightWithCondition(char),
    /// Stochastic weights that sum to zero (the symbol).
    #[error("rules for '{0}': the weights must sum to a positive number")]
    WeightSum(char),
    /// A grammar file's line that is no `key: value`.
    #[error("expected 'key: value'")]
    KeyValue,
    /// A grammar file's value that is not a number.
    #[error("'{value}' is not a number: {error}")]
    NotNumber {
        /// The value.
        value: String,
        /// The parser's words.
        error: std::num::ParseFloatError,
    },
    /// A grammar file's derivation count that is not a count.
    #[error("'{value}' is not a derivation count: {error}")]
    NotCount {
        /// The value.
        value: String,
        /// The parser's words.
        error: std::num::ParseIntError,
    },
    /// A grammar file's unknown key.
    #[error("unknown key '{0}' ({KEYS})")]
    UnknownKey(String),
    /// A grammar file without an axiom.
    #[error("no 'axiom:' line")]
    NoAxiom,
    /// A preset grove does not have.
    #[error("unknown preset '{name}' (known: {known})")]
    UnknownPreset {
        /// The name asked for.
        name: String,
        /// The presets, listed.
        known: String,
    },
    /// A derivation step past the symbol limit.
    #[error("derivation step {step} would give {symbols} symbols, more than the limit of {limit} (--max-symbols)")]
    TooManySymbols {
        /// The step.
        step: u32,
        /// The symbols it would give.
        symbols: u64,
        /// The limit.
        limit: u64,
    },
    /// A derivation step past the memory limit.
    #[error("derivation step {step} would need {bytes} bytes, more than the limit of {limit} (--max-bytes)")]
    DeriveBytes {
        /// The step.
        step: u32,
        /// The bytes it would need.
        bytes: u64,
        /// The limit.
        limit: u64,
    },
    /// The rayon pool of a derivation could not be built.
    #[error("{0}")]
    ThreadPool(rayon::ThreadPoolBuildError),
    /// An interpretation past the memory limit.
    #[error(
        "interpretation would need {bytes} bytes for {draws} segments, more than the limit of {limit} (--max-bytes)"
    )]
    InterpretBytes {
        /// The bytes it would need.
        bytes: u64,
        /// The segments it would draw.
        draws: u64,
        /// The limit.
        limit: u64,
    },
    /// A `]` without its `[` in a derived string.
    #[error("unbalanced brackets: ']' without '['")]
    UnbalancedClose,
    /// `[` without their `]` in a derived string (how many).
    #[error("unbalanced brackets: {0} '[' without ']'")]
    UnbalancedOpen(usize),
    /// A grammar the memoised turtle cannot interpret.
    #[error(
        "the memoised turtle needs one rule per symbol, without parameters, and balanced brackets in every successor"
    )]
    NotMemoisable,
    /// No GPU adapter.
    #[error("no GPU adapter available ({0}); install a Vulkan driver such as mesa-vulkan-drivers (lavapipe)")]
    Adapter(wgpu::RequestAdapterError),
    /// The adapter refused to open a device.
    #[error("cannot open the GPU device ({0})")]
    Device(wgpu::RequestDeviceError),
    /// Waiting for the GPU failed.
    #[error("waiting for the GPU failed ({0})")]
    Poll(wgpu::PollError),
    /// The readback's map callback never answered.
    #[error("the GPU readback was dropped: {0}")]
    ReadbackDropped(std::sync::mpsc::RecvError),
    /// Mapping the readback buffer failed.
    #[error("cannot read the GPU buffer ({0})")]
    Readback(wgpu::BufferAsyncError),
    /// The mapped readback buffer could not be viewed.
    #[error("cannot read the GPU buffer ({0:?})")]
    ReadbackRange(wgpu::MapRangeError),
    /// A grammar the GPU derivation does not handle (its name).
    #[error(
        "the GPU derivation handles grammars without parameters or conditions; derive '{0}' on the CPU (without --gpu)"
    )]
    GpuGrammar(String),
    /// A derivation step whose string could outgrow the GPU's 32-bit offsets.
    #[error("derivation step {step}: {symbols} symbols could grow past the GPU's 32-bit offsets; derive on the CPU")]
    GpuOffsets {
        /// The step.
        step: u32,
        /// The symbols before it.
        symbols: u64,
    },
    /// A derivation step whose string exceeds the GPU's largest storage buffer.
    #[error("derivation step {step}: {symbols} symbols exceed the GPU's largest storage buffer ({limit} bytes)")]
    GpuBinding {
        /// The step.
        step: u32,
        /// The symbols.
        symbols: u64,
        /// The device's largest storage binding, bytes.
        limit: u64,
    },
    /// A grammar that draws nothing (its name).
    #[error("'{0}' draws nothing (no F in the derived string)")]
    NoSegments(String),
    /// A model with more segments than a model may have.
    #[error("'{name}' has {segments} segments, more than a model's limit of {limit}; use a smaller --n")]
    TooManySegments {
        /// The grammar.
        name: String,
        /// Its segments.
        segments: usize,
        /// The most a model may have.
        limit: usize,
    },
    /// A model height that is not positive.
    #[error("the height must be a positive number of metres")]
    ModelHeight,
    /// Segments with positions or widths that are not finite (the grammar's name).
    #[error("'{0}' draws a segment at a position or width that is not a finite number; check its parameters")]
    NotFinite(String),
    /// Segments that all have zero length (the grammar's name).
    #[error("'{0}' draws nothing: every segment has zero length (check the parameters of F)")]
    ZeroLength(String),
    /// Segments too short to draw (the grammar's name).
    #[error("'{0}' draws nothing: its segments are too short to draw (check the parameters of F)")]
    TooShort(String),
    /// A model file that exists already.
    #[error("{}: already exists; choose another --out folder or remove it", .0.display())]
    Exists(PathBuf),
    /// A texture that exists already with other bytes.
    #[error("{}: already exists with other content; choose another --out folder", .0.display())]
    OtherContent(PathBuf),
    /// A folder that could not be created.
    #[error("{}: cannot create folder: {error}", path.display())]
    CreateFolder {
        /// The folder.
        path: PathBuf,
        /// The I/O error.
        error: std::io::Error,
    },
    /// A folder that could not be listed.
    #[error("{}: cannot list: {error}", path.display())]
    List {
        /// The folder.
        path: PathBuf,
        /// The I/O error.
        error: std::io::Error,
    },
    /// A file that could not be written or moved into place.
    #[error("{}: cannot write: {error}", path.display())]
    Write {
        /// The file.
        path: PathBuf,
        /// The I/O error.
        error: std::io::Error,
    },
    /// A texture that could not be written.
    #[error("{}: cannot write: {error}", path.display())]
    WriteImage {
        /// The file.
        path: PathBuf,
        /// The encoder's error.
        error: image::ImageError,
    },
    /// Reading a staged folder's entry failed.
    #[error("{0}")]
    Io(std::io::Error),
    /// The model written fails the check every model passes (the grammar's name).
    #[error("the model written for '{name}' is not valid: {error}")]
    Invalid {
        /// The grammar.
        name: String,
        /// Why the check refused it.
        error: crate::bank::BankError,
    },
}

impl LsystemError {
    /// This error in the part of a grammar named `at`: "`at`: error".
    pub fn at(self, at: impl std::fmt::Display) -> LsystemError {
        LsystemError::At { at: at.to_string(), error: Box::new(self) }
    }
}
