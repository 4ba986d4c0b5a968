//! What a glTF file must satisfy before grove draws it, beyond what the `gltf` crate validates:
//! its `asset.version` is 2.x, every extension it requires is one grove reads (compressed
//! geometry refused with the conversion that works), and every buffer view and accessor lies
//! inside its data. Errors are one line without the file name (the loader adds it).

use gltf::accessor::{DataType, Dimensions};

use super::accessor::MAX_COUNT;
use super::error::GltfProblem;

/// Extensions grove reads and draws: quantised attributes and WebP images (read before the
/// `gltf` crate sees the file, `gltf_open`), texture transforms and the specular strength.
pub const HANDLED: &[&str] =
    &["KHR_mesh_quantization", "KHR_texture_webp", "KHR_texture_transform", "KHR_materials_specular"];

/// Compressed-geometry extensions grove does not decode, each with the command that writes an
/// uncompressed copy grove reads (glTF-Transform's CLI; its author documents `cp` as the way to
/// decompress, donmccurdy/glTF-Transform#150).
pub const COMPRESSED: &[(&str, &str)] = &[
    (
        "KHR_draco_mesh_compression",
        "`npx @gltf-transform/cli cp IN out.glb` (glTF-Transform decodes Draco when it reads a file and writes plain buffers)",
    ),
    (
        "EXT_meshopt_compression",
        "`npx @gltf-transform/cli cp IN out.glb` (glTF-Transform decodes meshopt when it reads a file and writes plain buffers)",
    ),
];

/// Checks the extensions a file lists (`file` names it in the conversion hint): compressed
/// geometry and any other required extension grove does not read are refused by name. Returns
/// one warning for each extension the file uses without requiring it that grove ignores.
pub fn extensions(file: &str, required: &[String], used: &[String]) -> Result<Vec<String>, GltfProblem> {
    for (ext, fix) in COMPRESSED {
        if required.iter().chain(used).any(|e| e == ext) {
            return Err(GltfProblem::Compressed { ext, fix, file: file.to_string() });
        }
    }
    if let Some(ext) = required.iter().find(|e| !HANDLED.contains(&e.as_str())) {
        return Err(GltfProblem::Required(ext.clone()));
    }
    let mut warnings = Vec::new();
    for ext in used.iter().filter(|e| !HANDLED.contains(&e.as_str()) && !required.contains(e)) {
        if !warnings.iter().any(|w: &String| w.contains(ext.as_str())) {
            warnings.push(format!("uses the extension {ext}, which grove does not read; it is drawn without it"));
        }
    }
    Ok(warnings)
}

/// Checks `asset.version` (and `asset.minVersion`): glTF 2.x only.
pub fn version(doc: &gltf::Document) -> Result<(), GltfProblem> {
    let asset = &doc.as_json().asset;
    let major = |v: &str| v.split('.').next().and_then(|m| m.parse::<u32>().ok());
    let minor_ok =
        |v: &str| v.split_once('.').is_some_and(|(_, m)| !m.is_empty() && m.chars().all(|c| c.is_ascii_digit()));
    if major(&asset.version) != Some(2) || !minor_ok(&asset.version) {
        return Err(GltfProblem::Version(asset.version.clone()));
    }
    if let Some(min) = &asset.min_version {
        if major(min) != Some(2) || !minor_ok(min) || min.split_once('.').is_some_and(|(_, m)| m != "0") {
            return Err(GltfProblem::MinVersion(min.clone()));
        }
    }
    Ok(())
}

fn component_size(t: DataType) -> usize {
    match t {
        DataType::I8 | DataType::U8 => 1,
        DataType::I16 | DataType::U16 => 2,
        DataType::U32 | DataType::F32 => 4,
    }
}

/// The bytes of one element, columns of matrices padded to four bytes as glTF lays them out.
fn element_size(t: DataType, d: Dimensions) -> usize {
    let c = component_size(t);
    match d {
        Dimensions::Mat2 if c == 1 => 8,
        Dimensions::Mat3 if c == 1 => 12,
        Dimensions::Mat3 if c == 2 => 24,
        _ => c * d.multiplicity(),
    }
}

/// Checks that a run of `count` elements of `elem` bytes, `stride` apart, from `offset` inside
/// a view of `view_len` bytes, stays inside the view.
fn run_fits(offset: usize, count: usize, elem: usize, stride: usize, view_len: usize) -> bool {
    if count == 0 {
        return offset <= view_len;
    }
    stride
        .checked_mul(count - 1)
        .and_then(|x| x.checked_add(offset))
        .and_then(|x| x.checked_add(elem))
        .is_some_and(|end| end <= view_len)
}

/// Checks every buffer view against its buffer's data and every accessor (sparse parts
/// included) against its view, with checked arithmetic, so that a hostile count or offset is
/// refused by name before anything reads it.
pub fn bounds(doc: &gltf::Document, buffers: &[gltf::buffer::Data]) -> Result<(), GltfProblem> {
    for v in doc.views() {
        let len = buffers.get(v.buffer().index()).map_or(0, |b| b.0.len());
        if v.offset().checked_add(v.length()).is_none_or(|end| end > len) {
            return Err(GltfProblem::ViewPastBuffer { view: v.index(), buffer: v.buffer().index(), len });
        }
    }
    for a in doc.accessors() {
        let count = a.count();
        if count > MAX_COUNT {
            return Err(GltfProblem::TooManyElements { accessor: a.index(), count, max: MAX_COUNT });
        }
        let elem = element_size(a.data_type(), a.dimensions());
        if let Some(view) = a.view() {
            let stride = view.stride().unwrap_or(elem);
            if stride < elem || !run_fits(a.offset(), count, elem, stride, view.length()) {
                return Err(GltfProblem::AccessorPastView {
                    accessor: a.index(),
                    count,
                    elem,
                    offset: a.offset(),
                    view: view.index(),
                    view_len: view.length(),
                });
            }
        }
        if let Some(sparse) = a.sparse() {
            let n = sparse.count();
            if n > count {
                return Err(GltfProblem::SparseCount { accessor: a.index(), n, count });
            }
            let iv = sparse.indices().view();
            let isize = match sparse.indices().index_type() {
                gltf::accessor::sparse::IndexType::U8 => 1,
                gltf::accessor::sparse::IndexType::U16 => 2,
                gltf::accessor::sparse::IndexType::U32 => 4,
            };
            if !run_fits(sparse.indices().offset(), n, isize, isize, iv.length()) {
                return Err(GltfProblem::SparseIndicesPast(a.index()));
            }
            let vv = sparse.values().view();
            if !run_fits(sparse.values().offset(), n, elem, elem, vv.length()) {
                return Err(GltfProblem::SparseValuesPast(a.index()));
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn s(v: &[&str]) -> Vec<String> {
        v.iter().map(|x| x.to_string()).collect()
    }

    #[test]
    fn required_extensions_are_read_or_refused_by_name_and_used_ones_warned() {
        assert!(extensions("f", &s(&["KHR_texture_transform"]), &s(&["KHR_texture_transform"])).unwrap().is_empty());
        let e = extensions("f", &s(&["EXT_unknown"]), &s(&["EXT_unknown"])).unwrap_err().to_string();
        assert!(e.contains("EXT_unknown"), "{e}");
        let e = extensions("f.glb", &[], &s(&["KHR_draco_mesh_compression"])).unwrap_err().to_string();
        assert!(e.contains("KHR_draco_mesh_compression") && e.contains("cp f.glb"), "{e}");
        let w = extensions("f", &[], &s(&["KHR_materials_emissive_strength", "KHR_mesh_quantization"])).unwrap();
        assert_eq!(w.len(), 1);
        assert!(w[0].contains("KHR_materials_emissive_strength"));
    }

    #[test]
    fn runs_past_a_view_are_caught_without_overflow() {
        assert!(run_fits(0, 3, 2, 2, 6));
        assert!(!run_fits(0, 4, 2, 2, 6));
        assert!(!run_fits(0, u32::MAX as usize, 4, 4, 6));
        assert!(!run_fits(usize::MAX - 1, 2, 4, 4, 6));
        assert!(run_fits(6, 0, 4, 4, 6));
    }
}
