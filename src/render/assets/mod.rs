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

use std::path::PathBuf;

/// The assets folder: `$GROVE_ASSETS`, else `./assets` when it exists, else the source tree's.
pub fn default_assets_dir() -> PathBuf {
    if let Some(d) = std::env::var_os("GROVE_ASSETS") {
        return PathBuf::from(d);
    }
    let local = PathBuf::from("assets");
    if local.join("trees").is_dir() {
        return local;
    }
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/assets"))
}
