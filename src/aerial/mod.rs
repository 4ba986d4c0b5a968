//! Treetops from a registered pair of summer and winter aerial photographs (issue #21).
//!
//! After Ropinski et al. (2007): a texel belongs to a treetop when, over its k × k
//! neighbourhood, enough summer texels are green (G > R and G > B) and enough winter texels
//! are not, because deciduous trees lose their leaves in winter. Both photographs may first
//! be histogram-equalised per channel to even out the lighting of the two flights.
//!
//! The parts, each a plain function over images held in memory (CPU only):
//!
//! - [`raster`]: 8-bit RGB images, reading PNG and TIFF, writing PNG through a temporary file;
//! - [`equalize`]: per-channel histogram equalisation, computed in integers;
//! - [`mask`]: green flags and the k × k treetop rule, with window counts from running sums
//!   (time independent of k), parallel over bands of rows and identical on any thread count;
//! - [`crowns`]: 8-connected components of the mask (centroid, area, equivalent radius);
//! - [`synth`]: a synthetic park photographed straight down in summer and in winter, with truth;
//! - [`eval`]: precision, recall and F1 of a mask and of crown centres against that truth;
//! - [`scene`]: a grove scene with a tree at each crown;
//! - [`tiles`]: tiled mip pyramids of photographs of any size, streamed to disk (issue #22).
//!
//! Image coordinates: x to the right (east), y down (south), in pixels; pixel (i, j) covers
//! the square [i, i + 1) × [j, j + 1), so its centre is at (i + 0.5, j + 0.5). Metres are pixels
//! times the ground sample distance (GSD, metres per pixel), from the image's top-left corner.

pub mod crowns;
pub mod equalize;
mod error;
pub mod eval;
pub mod layers;
pub mod mask;
pub mod raster;
pub mod scene;
pub mod synth;
pub mod tiles;

pub use crowns::{Crown, label_crowns};
pub use equalize::{Luts, equalize_luts};
pub use error::AerialError;
pub use mask::{MaskParams, Segmenter};
pub use raster::RgbImage;
