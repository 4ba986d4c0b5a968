//! Reading vertex attributes of any component type as floats: `f32`, and the integer types
//! `KHR_mesh_quantization` allows (signed and unsigned bytes and shorts, normalised or not), with
//! byte strides and sparse substitutions, bounds-checked so that a hostile file gives an error,
//! never a panic.

use gltf::accessor::DataType;

use super::error::GltfProblem;

/// The most elements one accessor may have.
pub const MAX_COUNT: usize = 1 << 26;

/// Reads an accessor of `N` components per element as floats. Normalised integers map to
/// [0, 1] (unsigned) or [−1, 1] (signed) as glTF specifies; other integers keep their value.
pub fn read_floats<const N: usize>(
    acc: &gltf::Accessor,
    buffers: &[gltf::buffer::Data],
) -> Result<Vec<[f32; N]>, GltfProblem> {
    if acc.dimensions().multiplicity() != N {
        return Err(GltfProblem::Components {
            accessor: acc.index(),
            found: acc.dimensions().multiplicity(),
            expected: N,
        });
    }
    let count = acc.count();
    if count > MAX_COUNT {
        return Err(GltfProblem::AccessorTooLong { accessor: acc.index(), max: MAX_COUNT });
    }
    let size = match acc.data_type() {
        DataType::I8 | DataType::U8 => 1,
        DataType::I16 | DataType::U16 => 2,
        DataType::U32 | DataType::F32 => 4,
    };
    let elem = size * N;
    let norm = acc.normalized();
    let data_type = acc.data_type();
    let comp = |data: &[u8], at: usize| -> f32 {
        let b = &data[at..at + size];
        match data_type {
            DataType::F32 => f32::from_le_bytes([b[0], b[1], b[2], b[3]]),
            DataType::U32 => u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f32,
            DataType::I8 => {
                let v = b[0] as i8 as f32;
                if norm { (v / 127.0).max(-1.0) } else { v }
            }
            DataType::U8 => {
                let v = b[0] as f32;
                if norm { v / 255.0 } else { v }
            }
            DataType::I16 => {
                let v = i16::from_le_bytes([b[0], b[1]]) as f32;
                if norm { (v / 32767.0).max(-1.0) } else { v }
            }
            DataType::U16 => {
                let v = u16::from_le_bytes([b[0], b[1]]) as f32;
                if norm { v / 65535.0 } else { v }
            }
        }
    };
    let mut out: Vec<[f32; N]> = match acc.view() {
        None => vec![[0.0; N]; count],
        Some(view) => {
            let stride = view.stride().unwrap_or(elem);
            let buf = buffers.get(view.buffer().index()).ok_or(GltfProblem::MissingBuffer)?;
            let view_end = view
                .offset()
                .checked_add(view.length())
                .filter(|e| *e <= buf.0.len())
                .ok_or(GltfProblem::ViewPastItsBuffer)?;
            let start = view.offset() + acc.offset();
            if count > 0 {
                let end = stride
                    .checked_mul(count - 1)
                    .and_then(|x| x.checked_add(start + elem))
                    .ok_or(GltfProblem::AccessorTooLarge)?;
                if stride < elem || end > view_end {
                    return Err(GltfProblem::AccessorPastItsView(acc.index()));
                }
            }
            let data = &buf.0;
            (0..count).map(|i| std::array::from_fn(|k| comp(data, start + i * stride + k * size))).collect()
        }
    };
    if let Some(sparse) = acc.sparse() {
        // The substituted elements: `count` indices (increasing, each below the accessor's
        // count) and as many tightly packed values of the accessor's type.
        let n = sparse.count();
        let (iv, vv) = (sparse.indices().view(), sparse.values().view());
        let isize = match sparse.indices().index_type() {
            gltf::accessor::sparse::IndexType::U8 => 1,
            gltf::accessor::sparse::IndexType::U16 => 2,
            gltf::accessor::sparse::IndexType::U32 => 4,
        };
        let ibuf = buffers.get(iv.buffer().index()).ok_or(GltfProblem::SparseIndexBuffer)?;
        let vbuf = buffers.get(vv.buffer().index()).ok_or(GltfProblem::SparseValueBuffer)?;
        let istart = iv.offset() + sparse.indices().offset();
        let vstart = vv.offset() + sparse.values().offset();
        let fits = |start: usize, len: usize, within: usize, buf: usize| {
            start.checked_add(len).is_some_and(|e| e <= within && e <= buf)
        };
        let ilen = n.checked_mul(isize).ok_or(GltfProblem::SparseTooLarge)?;
        let vlen = n.checked_mul(elem).ok_or(GltfProblem::SparseTooLarge)?;
        if !fits(istart, ilen, iv.offset() + iv.length(), ibuf.0.len())
            || !fits(vstart, vlen, vv.offset() + vv.length(), vbuf.0.len())
        {
            return Err(GltfProblem::SparsePastViews(acc.index()));
        }
        for k in 0..n {
            let b = &ibuf.0[istart + k * isize..istart + (k + 1) * isize];
            let i = match isize {
                1 => b[0] as usize,
                2 => u16::from_le_bytes([b[0], b[1]]) as usize,
                _ => u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as usize,
            };
            let slot = out.get_mut(i).ok_or(GltfProblem::SparseIndex { accessor: acc.index(), index: i, count })?;
            *slot = std::array::from_fn(|c| comp(&vbuf.0, vstart + k * elem + c * size));
        }
    }
    Ok(out)
}
