//! [`AerialError`]: why an aerial photograph, mask, crown table, scene or tile pyramid could not
//! be read, checked or written. Its `Display` is one line, worded as the CLI prints it; the
//! errors it wraps are shown in that line rather than as a `source()`, since the CLI prints an
//! error's whole chain.

use std::path::PathBuf;

use grove_systems::files::FileError;

use super::layers::MAX_LAYERS;
use super::mask::MAX_K;
use super::raster::MAX_BYTES;
use super::tiles::{FORMAT, MAX_SIDE, TILE_RANGE, VERSION};

/// Why an aerial operation failed.
#[derive(Debug, thiserror::Error)]
pub enum AerialError {
    /// An error about a named file, folder or image: `name` is how the message names it (a path,
    /// "summer image a.png", "pyr: tile (0, 1) of mip 2").
    #[error("{name}: {error}")]
    In {
        /// The file or image, as the message names it.
        name: String,
        /// What went wrong with it.
        error: Box<AerialError>,
    },
    /// An image that `grove_systems::files` refused to open; `what` names it ("summer image").
    #[error("{what} {error}")]
    OpenImage {
        /// The image's role.
        what: String,
        /// Why it could not be opened (names the path).
        error: FileError,
    },
    /// A file that `grove_systems::files` refused to open (the message names the path).
    #[error("{0}")]
    File(FileError),
    /// The `summary.json` beside a crown table could not be opened.
    #[error("{0} (grove aerial segment writes it beside crowns.csv)")]
    NoSummary(FileError),
    /// A folder's `pyramid.ron` could not be opened.
    #[error("{0} (not a pyramid folder?)")]
    NoPyramidMeta(FileError),
    /// Reading or creating a file failed, in the words of `grove_systems::scene::io_message`.
    #[error("{}", grove_systems::scene::io_message(.0))]
    Access(std::io::Error),
    /// Writing, syncing, renaming or removing failed (the I/O error's own message).
    #[error("{0}")]
    Io(std::io::Error),
    /// Moving an existing pyramid aside failed.
    #[error("cannot move the old pyramid aside ({0})")]
    MoveAside(std::io::Error),
    /// The content starts with neither a PNG nor a TIFF signature.
    #[error("not a PNG or TIFF image")]
    NotPngOrTiff,
    /// A decoder (image, PNG, TIFF, RON, CSV) refused the content: its message on one line.
    #[error("{0}")]
    Decode(String),
    /// A PNG tile whose data ends early or is damaged: the decoder's message on one line.
    #[error("{0} (truncated or damaged tile)")]
    DamagedTile(String),
    /// An image that is not 8-bit RGB: its colour type in words.
    #[error("is {0}, not 8-bit RGB")]
    NotRgb8(String),
    /// An image too large for memory, or empty.
    #[error("{width} x {height} texels is outside 1 texel .. {} MiB", MAX_BYTES >> 20)]
    ImageSize {
        /// Width, texels.
        width: u32,
        /// Height, texels.
        height: u32,
    },
    /// An image or pyramid with a side outside 1 ..= [`MAX_SIDE`].
    #[error("{width} x {height} texels is outside 1 ..= {MAX_SIDE} per side")]
    Sides {
        /// Width, texels.
        width: u32,
        /// Height, texels.
        height: u32,
    },
    /// A source image the row reader refused: the decoder's message, or why the image cannot be
    /// streamed into a pyramid (interlaced, planar, not 8-bit…).
    #[error("{0}")]
    RowReader(String),
    /// An output path that is a folder.
    #[error("{} is a folder; it cannot be written as a file", .0.display())]
    IsFolder(PathBuf),
    /// An output that exists, without `--force`.
    #[error("{} already exists; pass --force to overwrite it", .0.display())]
    Exists(PathBuf),
    /// PNG encoding failed.
    #[error("{0}")]
    Png(png::EncodingError),
    /// Writing a CSV table failed.
    #[error("{0}")]
    Csv(csv::Error),
    /// Serializing as RON failed.
    #[error("{0}")]
    Ron(ron::Error),
    /// A table row that does not parse: its number (the header is row 1) and the reader's
    /// message on one line.
    #[error("row {row}: {message}")]
    Row {
        /// The row, counting the header as 1.
        row: usize,
        /// What the CSV reader said.
        message: String,
    },
    /// A crown row with a negative or non-finite number.
    #[error("row {0}: a negative, NaN or infinite number")]
    BadRow(usize),
    /// A crown with a non-finite position or size (before it is written).
    #[error("crown {0} has a position or size that is not a finite number; check --gsd")]
    CrownNotFinite(u32),
    /// A truth tree with a non-finite centre or a radius that is not positive.
    #[error("tree {0} has a bad centre or radius")]
    BadTree(u32),
    /// `summary.json` that does not parse.
    #[error("{0}")]
    Json(serde_json::Error),
    /// `summary.json` with an empty image or a ground resolution that is not positive.
    #[error("the image size and gsd_m must be positive")]
    SummarySize,
    /// A window side `--k` that is not odd or out of range.
    #[error("--k {0} must be odd and between 1 and {MAX_K}")]
    K(u32),
    /// A fraction `--s` or `--w` outside [0, 1).
    #[error("--{name} {value} must be a fraction in 0 <= {name} < 1")]
    Fraction {
        /// "s" or "w".
        name: &'static str,
        /// The value given.
        value: f64,
    },
    /// A summer and a winter image of different sizes (treetop masks).
    #[error("the summer image is {} x {} but the winter image is {} x {}; the pair must be registered and of equal size", summer.0, summer.1, winter.0, winter.1)]
    PairSize {
        /// Summer width and height.
        summer: (u32, u32),
        /// Winter width and height.
        winter: (u32, u32),
    },
    /// A summer and a winter photograph of different sizes (a scene's aerial section).
    #[error("aerial: the summer photograph is {}x{} but the winter one is {}x{}", summer.0, summer.1, winter.0, winter.1)]
    PhotographSizes {
        /// Summer width and height.
        summer: (u32, u32),
        /// Winter width and height.
        winter: (u32, u32),
    },
    /// A layer-mask path that is a folder (a pyramid).
    #[error("{}: the layer masks must be an image file (a tile pyramid would average their bits)", .0.display())]
    LayersAreFolder(PathBuf),
    /// A layer mask whose size differs from the photographs'.
    #[error("{}: the layer mask is {}x{} but the photographs are {}x{}", path.display(), mask.0, mask.1, photos.0, photos.1)]
    LayerMaskSize {
        /// The mask.
        path: PathBuf,
        /// Its width and height.
        mask: (u32, u32),
        /// The photographs' width and height.
        photos: (u32, u32),
    },
    /// A layer count outside 1 ..= [`MAX_LAYERS`].
    #[error("--layers {0} must be 1 to {MAX_LAYERS}")]
    LayerCount(u32),
    /// A layer's window side that is not odd or out of range.
    #[error("window side {0} must be odd and between 1 and {MAX_K}")]
    WindowSide(u32),
    /// The top layer's window below the base's.
    #[error("--k-top {top} must not be below --k {base}")]
    KTop {
        /// `--k-top`.
        top: u32,
        /// `--k`.
        base: u32,
    },
    /// A photographed area that is not positive.
    #[error("the photographed area {width} x {depth} m must be positive")]
    Area {
        /// East-west, metres.
        width: f64,
        /// North-south, metres.
        depth: f64,
    },
    /// No deciduous model of the asked kind in the catalogue.
    #[error("the model catalogue has no deciduous model of that kind")]
    NoModel,
    /// The generated scene crosses a limit.
    #[error("{0}")]
    Scene(grove_systems::limits::InvalidScene),
    /// The generated scene's text is over the scene size limit.
    #[error(
        "the scene of {trees} trees would be {bytes} bytes, over the limit of {} bytes every command applies to a scene; leave out small crowns with --min-radius",
        grove_systems::limits::MAX_SCENE_BYTES
    )]
    SceneTooBig {
        /// Trees in the scene.
        trees: usize,
        /// Its size in bytes, or an estimate ("about 123").
        bytes: String,
    },
    /// The generated scene's text does not load back.
    #[error("{0}")]
    SceneText(grove_systems::scene::SceneError),
    /// A pyramid's `format` field.
    #[error("format is {0:?}, not {FORMAT:?}")]
    PyramidFormat(String),
    /// A pyramid's format version.
    #[error("format version {0} is not supported (this grove reads version {VERSION})")]
    PyramidVersion(u32),
    /// A tile side that is not a power of two in [`TILE_RANGE`].
    #[error("tile side {0} must be a power of two from {lo} to {hi}", lo = TILE_RANGE.0, hi = TILE_RANGE.1)]
    TileSide(u32),
    /// A pyramid's channel count.
    #[error("{0} channels; a pyramid has 1 (grey) or 3 (RGB)")]
    Channels(u8),
    /// A pyramid's level count that does not fit its size and tile.
    #[error("{levels} levels, but a {width} x {height} image in tiles of {tile} has {expected}")]
    Levels {
        /// The levels written.
        levels: u32,
        /// Width, texels.
        width: u32,
        /// Height, texels.
        height: u32,
        /// Tile side.
        tile: u32,
        /// The levels such an image has.
        expected: u32,
    },
    /// A pyramid's fingerprint that is not 16 hex digits.
    #[error("fingerprint {0:?} is not 16 hexadecimal digits")]
    Fingerprint(String),
    /// A pyramid's tile format other than PNG.
    #[error("tile format {0:?} is not supported (only \"png\")")]
    TileFormat(String),
    /// A pyramid path that is not a folder.
    #[error("{}: not a folder (a pyramid is a folder written by `grove aerial tile`)", .0.display())]
    NotPyramidFolder(PathBuf),
    /// A `pyramid.ron` over its size limit, KiB.
    #[error("longer than {0} KiB; not a pyramid description")]
    MetaTooLong(u64),
    /// A pyramid made from another image.
    #[error("{}: this pyramid was made from another image (fingerprint {found}, expected {expected}); tile the right image again", dir.display())]
    OtherImage {
        /// The pyramid.
        dir: PathBuf,
        /// Its fingerprint.
        found: String,
        /// The one asked for.
        expected: String,
    },
    /// A mip the pyramid does not have.
    #[error("mip {mip} does not exist (the pyramid has {levels})")]
    NoMip {
        /// The mip asked for.
        mip: u32,
        /// The pyramid's levels.
        levels: u32,
    },
    /// A tile outside its mip.
    #[error("tile ({tx}, {ty}) of mip {mip} does not exist (the mip has {nx} x {ny})")]
    NoTile {
        /// Column.
        tx: u32,
        /// Row.
        ty: u32,
        /// Mip.
        mip: u32,
        /// Tiles across.
        nx: u32,
        /// Tiles down.
        ny: u32,
    },
    /// A tile of the wrong size or colour type.
    #[error(
        "is {width} x {height} {colour:?}, expected {expected_width} x {expected_height} {expected_colour:?}; the tile does not belong to this pyramid"
    )]
    ForeignTile {
        /// Its width.
        width: u32,
        /// Its height.
        height: u32,
        /// Its colour type.
        colour: png::ColorType,
        /// The width it should have.
        expected_width: u32,
        /// The height it should have.
        expected_height: u32,
        /// The colour type it should have.
        expected_colour: png::ColorType,
    },
    /// A tile destination that exists and is not a folder.
    #[error("{}: exists and is not a folder", .0.display())]
    OutNotFolder(PathBuf),
    /// A tile destination that is a folder but no pyramid.
    #[error("{}: exists and is not a pyramid folder (no {}); choose another --out", .0.display(), super::tiles::META_FILE)]
    OutNotPyramid(PathBuf),
    /// A pyramid at the destination, without `--force`.
    #[error("{}: a pyramid is already there; pass --force to replace it", .0.display())]
    PyramidExists(PathBuf),
    /// A source image without rows.
    #[error("the image has no rows")]
    NoRows,
}

impl AerialError {
    /// This error about the file, folder or image named `name`: "`name`: error".
    pub fn named(self, name: impl std::fmt::Display) -> AerialError {
        AerialError::In { name: name.to_string(), error: Box::new(self) }
    }
}
