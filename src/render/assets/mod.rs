//! Assets the renderer uploads: textures ([`textures`]: 2D uploads with mip chains, the
//! environment cubemap and its irradiance). Models are loaded on the CPU by [`crate::models`].

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
