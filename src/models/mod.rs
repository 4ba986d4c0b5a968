//! Tree models on the CPU: glTF 2.0 files loaded, checked and measured, without a GPU. The
//! renderer uploads what is loaded here ([`ModelData`]); the model banks, the species and
//! L-system generators and the model checks use the same loader and measurements.
//!
//! - [`gltf_load`]: loading a file into [`ModelData`] ([`load_model`]), every feature of the file
//!   drawn or refused by name; the file and every buffer and image it names are read through
//!   `grove_systems::files` ([`gltf_files`]), opened and checked ([`gltf_open`], [`gltf_check`],
//!   [`accessor`]) and flattened into triangle lists ([`gltf_prim`]), with wind channels computed
//!   where the file has none ([`wind_channels`]);
//! - [`mesh`]: the loaded model's types (vertices, primitives, materials, images);
//! - [`measure`]: what a catalogue says about a model (bounds, crown radius, triangles, kind),
//!   with its pick shape ([`pick`]);
//! - [`error`]: [`GltfError`] and [`GltfProblem`], why a file is refused, in one line.

pub mod accessor;
pub mod error;
pub mod gltf_check;
pub mod gltf_files;
pub mod gltf_load;
pub mod gltf_open;
pub mod gltf_prim;
pub mod measure;
pub mod mesh;
pub mod pick;
pub mod wind_channels;

pub use error::{GltfError, GltfProblem};
pub use gltf_load::load_model;
pub use measure::{Measured, measure};
pub use mesh::{ImageData, MaterialData, ModelData, PrimitiveData, Vertex};
