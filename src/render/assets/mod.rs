//! Assets the renderer loads: glTF 2.0 models with the shared mesh types ([`gltf_load`]:
//! `ModelData`, `Vertex`) and textures ([`textures`]: 2D uploads with mip chains, the
//! environment cubemap and its irradiance).

pub mod accessor;
pub mod gltf_check;
pub mod gltf_files;
pub mod gltf_load;
pub mod gltf_open;
pub mod gltf_prim;
pub mod model;
pub mod wind_channels;
pub mod textures;
