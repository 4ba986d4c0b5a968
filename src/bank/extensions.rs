//! The glTF extensions grove cannot read, found before the `gltf` crate sees the file, so that
//! the error names the extension (and, for compressed geometry, a conversion that works)
//! instead of "not a valid glTF". The lists live with the loader (`models::gltf_check`),
//! which applies the same check to every model it loads.

use std::path::Path;

use grove_systems::files::{self, Kind};

use super::BankError;

pub use crate::models::gltf_check::COMPRESSED as REFUSED;
pub use crate::models::gltf_open::{extensions_of, json_of};

/// Refuses a file that uses an extension grove cannot decode or requires one it does not read:
/// one line naming the extension (and the conversion). Files that cannot be read or do not
/// parse pass, for the loader to report.
pub fn check_file(path: &Path) -> Result<(), BankError> {
    let Ok(bytes) = files::read(path, Kind::Gltf) else { return Ok(()) };
    let (required, used) = extensions_of(&bytes);
    let shown = path.display().to_string();
    crate::models::gltf_check::extensions(&shown, &required, &used)
        .map(|_| ())
        .map_err(|problem| BankError::Extension { file: shown.clone(), problem })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_glb_json_chunk_is_found_and_compressed_files_are_refused_with_the_extension_named() {
        let json = br#"{"asset":{"version":"2.0"},"extensionsUsed":["KHR_draco_mesh_compression"],"extensionsRequired":["KHR_draco_mesh_compression"]}"#;
        let mut glb = b"glTF".to_vec();
        glb.extend(2u32.to_le_bytes());
        glb.extend(((20 + json.len()) as u32).to_le_bytes());
        glb.extend((json.len() as u32).to_le_bytes());
        glb.extend(b"JSON");
        glb.extend(json);
        let (req, _) = extensions_of(&glb);
        assert_eq!(req, vec!["KHR_draco_mesh_compression".to_string()]);
        let dir = std::env::temp_dir().join(format!("grove-ext-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let f = dir.join("draco.glb");
        std::fs::write(&f, &glb).unwrap();
        let e = check_file(&f).unwrap_err().to_string();
        assert!(e.contains("KHR_draco_mesh_compression") && e.contains("gltf-transform") && !e.contains('\n'), "{e}");
        std::fs::write(&f, br#"{"asset":{"version":"2.0"}}"#).unwrap();
        assert!(check_file(&f).is_ok());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
