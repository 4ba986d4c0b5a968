//! Opening a glTF file for the loader, including the required extensions grove reads itself,
//! which the `gltf` crate's validation would refuse as unsupported: `KHR_mesh_quantization`
//! (whose integer attributes [`super::accessor`] decodes) and `KHR_texture_webp` (a texture's
//! WebP image, decoded by the `image` crate). They are taken out of `extensionsRequired`, and a
//! texture whose only image is its `KHR_texture_webp` source gets that image as its `source`,
//! before the crate validates the rest of the file as usual.

/// Required extensions grove reads although the `gltf` crate does not list them.
pub const READ_HERE: &[&str] = &["KHR_mesh_quantization", "KHR_texture_webp"];

/// The JSON chunk of a `.glb` file, or the whole text of a `.gltf` file.
pub fn json_of(bytes: &[u8]) -> Option<&[u8]> {
    if bytes.len() >= 4 && &bytes[0..4] == b"glTF" {
        if bytes.len() < 20 || &bytes[16..20] != b"JSON" {
            return None;
        }
        let len = u32::from_le_bytes(bytes[12..16].try_into().ok()?) as usize;
        bytes.get(20..20usize.checked_add(len)?)
    } else {
        Some(bytes)
    }
}

/// The names in the file's `extensionsRequired` and `extensionsUsed`, as far as its JSON can be
/// read (an unreadable file gives none; the `gltf` crate then names the fault).
pub fn extensions_of(bytes: &[u8]) -> (Vec<String>, Vec<String>) {
    let Some(json) = json_of(bytes) else { return (Vec::new(), Vec::new()) };
    let Ok(v) = serde_json::from_slice::<serde_json::Value>(json) else { return (Vec::new(), Vec::new()) };
    let list = |key: &str| -> Vec<String> {
        v.get(key)
            .and_then(|x| x.as_array())
            .map(|a| a.iter().filter_map(|s| s.as_str().map(String::from)).collect())
            .unwrap_or_default()
    };
    (list("extensionsRequired"), list("extensionsUsed"))
}

/// The file's bytes with [`READ_HERE`] removed from `extensionsRequired` (a `.glb` rebuilt with
/// the new JSON chunk and its binary chunk unchanged), or `None` when nothing needs removing.
fn without_handled(bytes: &[u8]) -> Option<Vec<u8>> {
    let json = json_of(bytes)?;
    let mut v: serde_json::Value = serde_json::from_slice(json).ok()?;
    let mut changed = false;
    if let Some(req) = v.get_mut("extensionsRequired").and_then(|r| r.as_array_mut()) {
        let before = req.len();
        req.retain(|e| !e.as_str().is_some_and(|s| READ_HERE.contains(&s)));
        changed |= req.len() != before;
    }
    if let Some(textures) = v.get_mut("textures").and_then(|t| t.as_array_mut()) {
        for t in textures.iter_mut().filter_map(|t| t.as_object_mut()) {
            let webp =
                t.get("extensions").and_then(|e| e.get("KHR_texture_webp")).and_then(|w| w.get("source")).cloned();
            if let (None, Some(src)) = (t.get("source"), webp) {
                t.insert("source".into(), src);
                changed = true;
            }
        }
    }
    if !changed {
        return None;
    }
    let mut text = serde_json::to_vec(&v).ok()?;
    if &bytes[0..4.min(bytes.len())] != b"glTF" {
        return Some(text);
    }
    while text.len() % 4 != 0 {
        text.push(b' ');
    }
    let old_json_len = u32::from_le_bytes(bytes[12..16].try_into().ok()?) as usize;
    let rest = bytes.get(20 + old_json_len..)?;
    let total = 12 + 8 + text.len() + rest.len();
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(&bytes[0..8]);
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(text.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&text);
    out.extend_from_slice(rest);
    Some(out)
}

/// Parses and validates a glTF or GLB file's bytes (see the module docs).
pub fn parse(bytes: &[u8]) -> gltf::Result<gltf::Gltf> {
    let handled = without_handled(bytes);
    let bytes = handled.as_deref().unwrap_or(bytes);
    positions_in_range(&gltf::Gltf::from_slice_without_validation(bytes)?)?;
    gltf::Gltf::from_slice(bytes)
}

/// The one index the `gltf` crate's own validation follows without checking it first (a
/// primitive's `POSITION` accessor, for its `min` and `max`): out of range, it is refused here
/// as the crate refuses every other index, instead of reaching an index out of bounds there.
fn positions_in_range(g: &gltf::Gltf) -> gltf::Result<()> {
    use gltf::json::validation::{Checked, Error};
    let root = g.document.as_json();
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, prim) in mesh.primitives.iter().enumerate() {
            if let Some(i) = prim.attributes.get(&Checked::Valid(gltf::json::mesh::Semantic::Positions))
                && i.value() >= root.accessors.len()
            {
                let path = gltf::json::Path::new()
                    .field("meshes")
                    .index(m)
                    .field("primitives")
                    .index(p)
                    .field("attributes")
                    .key("POSITION");
                return Err(gltf::Error::Validation(vec![(path, Error::IndexOutOfBounds)]));
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_the_handled_extension_leaves_extensions_required_in_gltf_and_glb() {
        let json = br#"{"asset":{"version":"2.0"},"extensionsUsed":["KHR_mesh_quantization"],"extensionsRequired":["KHR_mesh_quantization"]}"#;
        assert!(gltf::Gltf::from_slice(json).is_err(), "the crate alone refuses it");
        assert!(parse(json).is_ok());
        let mut glb = b"glTF".to_vec();
        glb.extend(2u32.to_le_bytes());
        glb.extend(((20 + json.len()) as u32).to_le_bytes());
        glb.extend((json.len() as u32).to_le_bytes());
        glb.extend(b"JSON");
        glb.extend(json);
        assert!(parse(&glb).is_ok());
        // A WebP-only texture gets its WebP image as its source.
        let webp = br#"{"asset":{"version":"2.0"},"extensionsRequired":["KHR_texture_webp"],"images":[{"uri":"a.webp"}],"textures":[{"extensions":{"KHR_texture_webp":{"source":0}}}]}"#;
        let g = parse(webp).unwrap();
        assert_eq!(g.document.textures().next().unwrap().source().index(), 0);
        let other = br#"{"asset":{"version":"2.0"},"extensionsRequired":["KHR_mesh_quantization","EXT_unknown"]}"#;
        assert!(parse(other).is_err(), "an unknown required extension is still refused");
    }
}
