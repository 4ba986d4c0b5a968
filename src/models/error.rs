//! [`GltfError`]: why a glTF model could not be read or is refused, and [`GltfProblem`], what is
//! wrong inside the file (its `Display` without the file's name, which [`GltfError`] adds).

use std::path::PathBuf;

use grove_systems::files::FileError;

/// Why a glTF model could not be loaded.
#[derive(Debug, thiserror::Error)]
pub enum GltfError {
    /// The file could not be read (the message names the path).
    #[error("{0}")]
    File(FileError),
    /// The file is read but refused: "`path`: problem".
    #[error("{}: {problem}", path.display())]
    Model {
        /// The model file.
        path: PathBuf,
        /// What is wrong with it.
        problem: GltfProblem,
    },
}

/// What is wrong in a glTF file, a buffer, an image or a primitive of it: one line without the
/// file's name.
#[derive(Clone, Debug, thiserror::Error)]
pub enum GltfProblem {
    /// A compressed-geometry extension: the command that writes a copy grove reads (`IN` in
    /// `fix` stands for the file).
    #[error("uses {ext}, which grove does not decode; convert it first with {}", fix.replace("IN", file))]
    Compressed {
        /// The extension.
        ext: &'static str,
        /// The conversion, with `IN` for the file.
        fix: &'static str,
        /// The file, as shown.
        file: String,
    },
    /// A required extension grove does not read.
    #[error("requires the extension {0}, which grove does not read")]
    Required(String),
    /// The `gltf` crate refused the file: its message on one line.
    #[error("not a valid glTF 2.0 file ({0})")]
    Parse(String),
    /// An `asset.version` other than 2.x.
    #[error("asset.version is \"{0}\"; grove reads glTF 2.x files only")]
    Version(String),
    /// An `asset.minVersion` other than 2.0.
    #[error("asset.minVersion is \"{0}\"; grove reads glTF 2.0")]
    MinVersion(String),
    /// A problem with a URI the file names: `what` is "buffer" or "texture".
    #[error("{what} '{uri}': {problem}")]
    Uri {
        /// "buffer" or "texture".
        what: &'static str,
        /// The URI.
        uri: String,
        /// What is wrong with it.
        problem: Box<GltfProblem>,
    },
    /// A problem with a named part: a buffer ("buffer 0", "buffer 'a.bin'") or an image
    /// ("texture 'a.png'", "image 1").
    #[error("{name}: {problem}")]
    Part {
        /// The part, as the message names it.
        name: String,
        /// What is wrong with it.
        problem: Box<GltfProblem>,
    },
    /// A problem with a primitive ("mesh 'leaf' primitive 0").
    #[error("{name} {problem}")]
    Primitive {
        /// The primitive, as the message names it.
        name: String,
        /// What is wrong with it.
        problem: Box<GltfProblem>,
    },
    /// The node hierarchy is too large or has a cycle.
    #[error("the node hierarchy is too large or cyclic")]
    NodeHierarchy,
    /// Nothing to draw.
    #[error("has no triangles to draw")]
    NoTriangles,
    /// A vertex position is NaN or infinite.
    #[error("has non-finite vertex positions")]
    NonFinite,
    /// The model is flat after its node transforms.
    #[error(
        "is {height} m tall after its node transforms (bounds {min:?} to {max:?}); a model must have height (an all-zero or flattening node matrix?)"
    )]
    Flat {
        /// Its height, metres.
        height: f32,
        /// The bounds' low corner.
        min: [f32; 3],
        /// The bounds' high corner.
        max: [f32; 3],
    },
    /// An image's buffer view outside the buffers.
    #[error("buffer view out of range")]
    ImageView,
    /// An image that does not decode: the decoder's message on one line.
    #[error("cannot decode ({0})")]
    Decode(String),
    /// An image empty or over 16384 texels a side.
    #[error("unsupported size {width}x{height}")]
    ImageSize {
        /// Width, texels.
        width: u32,
        /// Height, texels.
        height: u32,
    },
    /// A URI with a scheme.
    #[error("is a URL; grove reads only files beside the model or below it")]
    Url,
    /// A URI with a bad `%` escape.
    #[error("has a broken %-escape")]
    BrokenEscape,
    /// A URI that is not UTF-8 once decoded.
    #[error("is not UTF-8 once %-escapes are decoded")]
    NotUtf8,
    /// A URI with `..` or an absolute path.
    #[error(
        "lies outside the model's folder ('..' or an absolute path); grove reads only files beside the model or below it"
    )]
    Outside,
    /// A URI that leads out of the folder through a symbolic link.
    #[error("leads out of the model's folder through a symbolic link; grove reads only files inside it")]
    SymlinkOut,
    /// A file named by a URI that `grove_systems::files` refused (its reason, without the path).
    #[error("{}", .0.reason())]
    Unreadable(FileError),
    /// A `data:` URI was expected.
    #[error("not a data URI")]
    NotDataUri,
    /// A `data:` URI that is not base64.
    #[error("is a data URI that is not base64")]
    NotBase64Uri,
    /// Invalid base64 in a `data:` URI.
    #[error("has invalid base64")]
    InvalidBase64,
    /// A buffer naming the GLB binary chunk of a file without one.
    #[error("buffer {0} names the binary chunk, which the file lacks")]
    NoBinChunk(usize),
    /// A buffer shorter than its `byteLength`.
    #[error("{name} has {len} bytes, fewer than its byteLength {byte_length}")]
    ShortBuffer {
        /// The buffer, as the message names it.
        name: String,
        /// Its bytes.
        len: usize,
        /// Its `byteLength`.
        byte_length: usize,
    },
    /// A buffer view past the end of its buffer.
    #[error("buffer view {view} runs past the end of buffer {buffer} ({len} bytes)")]
    ViewPastBuffer {
        /// The view.
        view: usize,
        /// The buffer.
        buffer: usize,
        /// The buffer's bytes.
        len: usize,
    },
    /// An accessor with more elements than grove reads.
    #[error("accessor {accessor} has {count} elements, more than the {max} grove reads")]
    TooManyElements {
        /// The accessor.
        accessor: usize,
        /// Its elements.
        count: usize,
        /// The most grove reads.
        max: usize,
    },
    /// An accessor past the end of its buffer view.
    #[error(
        "accessor {accessor} ({count} elements of {elem} bytes from byte {offset}) runs past its buffer view {view} of {view_len} bytes"
    )]
    AccessorPastView {
        /// The accessor.
        accessor: usize,
        /// Its elements.
        count: usize,
        /// Bytes per element.
        elem: usize,
        /// Its offset in the view.
        offset: usize,
        /// The view.
        view: usize,
        /// The view's bytes.
        view_len: usize,
    },
    /// A sparse accessor replacing more elements than it has.
    #[error("accessor {accessor} replaces {n} of its {count} elements")]
    SparseCount {
        /// The accessor.
        accessor: usize,
        /// Elements replaced.
        n: usize,
        /// Its elements.
        count: usize,
    },
    /// Sparse indices past their view (the accessor).
    #[error("the sparse indices of accessor {0} run past their buffer view")]
    SparseIndicesPast(usize),
    /// Sparse values past their view (the accessor).
    #[error("the sparse values of accessor {0} run past their buffer view")]
    SparseValuesPast(usize),
    /// An accessor with another number of components than read.
    #[error("accessor {accessor} has {found} components, {expected} expected")]
    Components {
        /// The accessor.
        accessor: usize,
        /// Its components.
        found: usize,
        /// The components read.
        expected: usize,
    },
    /// An accessor with more elements than grove reads, found while reading it.
    #[error("accessor {accessor} has more than {max} elements")]
    AccessorTooLong {
        /// The accessor.
        accessor: usize,
        /// The most grove reads.
        max: usize,
    },
    /// A buffer view naming a missing buffer.
    #[error("a buffer view names a missing buffer")]
    MissingBuffer,
    /// A buffer view past its buffer, found while reading.
    #[error("a buffer view runs past its buffer")]
    ViewPastItsBuffer,
    /// An accessor whose extent overflows.
    #[error("an accessor is too large")]
    AccessorTooLarge,
    /// An accessor past its view, found while reading.
    #[error("accessor {0} runs past its buffer view")]
    AccessorPastItsView(usize),
    /// A sparse index view naming a missing buffer.
    #[error("a sparse index view names a missing buffer")]
    SparseIndexBuffer,
    /// A sparse value view naming a missing buffer.
    #[error("a sparse value view names a missing buffer")]
    SparseValueBuffer,
    /// A sparse part whose extent overflows.
    #[error("a sparse accessor is too large")]
    SparseTooLarge,
    /// A sparse part past its views, found while reading (the accessor).
    #[error("the sparse part of accessor {0} runs past its buffer views")]
    SparsePastViews(usize),
    /// A sparse index past the accessor's elements.
    #[error("accessor {accessor} has a sparse index {index} past its {count} elements")]
    SparseIndex {
        /// The accessor.
        accessor: usize,
        /// The index.
        index: usize,
        /// Its elements.
        count: usize,
    },
    /// A material whose textures read different coordinate sets.
    #[error(
        "material '{material}' reads its {what} texture through TEXCOORD_{other} and its {first} texture through TEXCOORD_{set}; grove draws a material with one set of texture coordinates"
    )]
    TexCoordSets {
        /// The material's name.
        material: String,
        /// The texture that differs.
        what: &'static str,
        /// Its set.
        other: u32,
        /// The first texture.
        first: &'static str,
        /// Its set.
        set: u32,
    },
    /// A material whose textures have different transforms.
    #[error(
        "material '{material}' gives its {what} texture another KHR_texture_transform than its {first} texture; grove draws a material with one texture transform"
    )]
    TextureTransforms {
        /// The material's name.
        material: String,
        /// The texture that differs.
        what: &'static str,
        /// The first texture.
        first: &'static str,
    },
    /// A primitive of points.
    #[error("draws points, which grove does not draw")]
    Points,
    /// A primitive of lines (its mode).
    #[error("draws lines ({0:?}), which grove does not draw")]
    Lines(gltf::mesh::Mode),
    /// A morph target of another length than its vertices.
    #[error("morph target accessor {accessor} has {len} elements for {vertices} vertices")]
    MorphLength {
        /// The target's accessor.
        accessor: usize,
        /// Its elements.
        len: usize,
        /// The primitive's vertices.
        vertices: usize,
    },
    /// Morph targets and default weights of different counts.
    #[error("has {targets} morph targets and {weights} default weights")]
    MorphWeights {
        /// Morph targets.
        targets: usize,
        /// Default weights.
        weights: usize,
    },
    /// Indices that cannot be read.
    #[error("has indices that cannot be read")]
    UnreadableIndices,
    /// An index past the vertices.
    #[error("has an index past its vertices")]
    IndexPastVertices,
    /// A primitive without the coordinate set its material reads.
    #[error("has no TEXCOORD_{0} although its material's textures read it")]
    NoTexCoord(u32),
    /// Vertex attributes of different lengths.
    #[error("has attributes of different lengths")]
    AttributeLengths,
}
