//! The limits on what grove reads, stated once.
//!
//! Every file grove reads can ask for work and memory: a recording names ticks to simulate, a
//! scene names grid cells, holes and triangles to build. These constants bound that work, so
//! that any input, however hostile, is either refused at once with one line naming the limit or
//! runs in bounded time and memory. `docs/scenes.md` and `docs/replay-format.md` list them.
//!
//! A limit is raised by changing its constant here and rebuilding grove; the error messages say
//! so ([`RAISE`]).

crate::message_error::message_error! {
    /// Why a scene, or one of its parts (a plane, the sun, the wind, a scatter, water, grass, the
    /// aerial ground and its crowns), is refused, a crossed limit among other things: one line
    /// naming the part and what is wrong.
    InvalidScene
}

/// How an error message tells the user to raise a limit.
pub const RAISE: &str = "raise it in systems/src/limits.rs and rebuild grove";

/// The longest tick a recording may name: 10^8 ticks, about 19 days at 60 Hz.
pub const MAX_TICKS: u64 = 100_000_000;

/// The longest line of a recording, bytes (1 MiB).
pub const MAX_LINE_BYTES: usize = 1 << 20;

/// The largest scene file, bytes (8 MiB), whether given on the command line or named by a
/// recording.
pub const MAX_SCENE_BYTES: u64 = 8 << 20;

/// The largest scene handed over as text (a headset's room sent with a session's open request,
/// a scene given to the WebAssembly module), bytes (1 MiB): its JSON string, at most twice as
/// long, fits the body of an open request (`src/serve/api.rs`).
pub const MAX_SCENE_TEXT_BYTES: u64 = 1 << 20;

/// The largest file of a model (a glTF file, a buffer or image it names, a file of a model
/// bank), bytes (512 MiB).
pub const MAX_MODEL_FILE_BYTES: u64 = 512 << 20;

/// The most grid cells of all the grid planes of one scene together (a cell is two triangles).
/// An explicit mesh counts one cell per two triangles. At about 400 bytes per cell once built
/// (vertices, triangles and the ray-cast tree), this keeps a scene under about 100 MB.
pub const MAX_SCENE_CELLS: u64 = 250_000;

/// The most holes in one grid plane.
pub const MAX_HOLES_PER_PLANE: usize = 10_000;

/// The most planes in one scene.
pub const MAX_PLANES: usize = 64;

/// The most trees a scene may place at the start.
pub const MAX_SCENE_TREES: usize = 100_000;

/// The most scatters in one scene; the trees they can place count towards [`MAX_SCENE_TREES`].
pub const MAX_SCATTERS: usize = 64;

/// The most water bodies in one scene.
pub const MAX_WATER_BODIES: usize = 64;

/// The most vertices of one water body's outline (its simplicity check is quadratic in them).
pub const MAX_WATER_VERTICES: usize = 1024;

/// The largest absolute coordinate, size, radius or elevation in a scene, metres (10^6 m).
pub const MAX_COORD: f32 = 1.0e6;

/// The smallest grid cell, metres (1 mm).
pub const MIN_CELL: f32 = 1.0e-3;

/// The smallest grid cell relative to the plane's distance from the origin: a cell must be at
/// least this fraction of the largest absolute coordinate of the plane, so that single-precision
/// vertices stay at least a few hundred units of least precision apart.
pub const MIN_CELL_RELATIVE: f32 = 1.0e-5;

/// The most grass patches in one scene.
pub const MAX_GRASS_PATCHES: usize = 64;

/// The most blades all the blade patches of one scene may place together (2^22, about 4.2
/// million; 32 bytes each on the GPU).
pub const MAX_GRASS_BLADES: u64 = 1 << 22;

/// The most points of a grass patch's polygon.
pub const MAX_GRASS_POLYGON: usize = 4096;

/// The largest recording file, bytes (4 GiB; it is read line by line, each line within
/// [`MAX_LINE_BYTES`]).
pub const MAX_RECORDING_BYTES: u64 = 4 << 30;

/// The largest L-system grammar file, bytes (1 MiB).
pub const MAX_GRAMMAR_BYTES: u64 = 1 << 20;

/// The largest table of numbers (a `crowns.csv`), bytes (64 MiB).
pub const MAX_TABLE_BYTES: u64 = 64 << 20;

/// The largest small settings or index file (a bank's catalogue, a task, a pyramid's index),
/// bytes (4 MiB).
pub const MAX_INDEX_BYTES: u64 = 4 << 20;

/// The largest image file, bytes (1 GiB); decoders also bound an image by the dimensions its
/// header states.
pub const MAX_IMAGE_FILE_BYTES: u64 = 1 << 30;

/// The largest cache file grove reads back (an impostor atlas), bytes (256 MiB).
pub const MAX_CACHE_BYTES: u64 = 256 << 20;

/// The most ticks a scenario file (`docs/scenarios.md`) may ask for, its waits, touchpad holds
/// and wait-until timeouts added up: 360,000 ticks, 100 minutes at 60 Hz.
pub const MAX_SCENARIO_TICKS: u64 = 360_000;

/// The largest scenario file, bytes (4 MiB).
pub const MAX_SCENARIO_BYTES: u64 = 4 << 20;

/// The most steps and expectations a scenario file may list, together.
pub const MAX_SCENARIO_STEPS: usize = 100_000;
