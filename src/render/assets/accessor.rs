//! Reading vertex attributes of any component type as floats: `f32`, and the integer types
//! `KHR_mesh_quantization` allows (signed and unsigned bytes and shorts, normalised or not), with
//! byte strides, bounds-checked so that a hostile file gives an error, never a panic.

use gltf::accessor::DataType;

/// The most elements one accessor may have.
pub const MAX_COUNT: usize = 1 << 26;

/// Reads an accessor of `N` components per element as floats. Normalised integers map to
/// [0, 1] (unsigned) or [−1, 1] (signed) as glTF specifies; other integers keep their value.
pub fn read_floats<const N: usize>(acc: &gltf::Accessor, buffers: &[gltf::buffer::Data]) -> Result<Vec<[f32; N]>, String> {
    if acc.dimensions().multiplicity() != N {
        return Err(format!("accessor {} has {} components, {N} expected", acc.index(), acc.dimensions().multiplicity()));
    }
    if acc.sparse().is_some() {
        return Err(format!("accessor {} is sparse, which grove does not read", acc.index()));
    }
    let count = acc.count();
    if count > MAX_COUNT {
        return Err(format!("accessor {} has more than {MAX_COUNT} elements", acc.index()));
    }
    let Some(view) = acc.view() else { return Ok(vec![[0.0; N]; count]) };
    let size = match acc.data_type() {
        DataType::I8 | DataType::U8 => 1,
        DataType::I16 | DataType::U16 => 2,
        DataType::U32 | DataType::F32 => 4,
    };
    let elem = size * N;
    let stride = view.stride().unwrap_or(elem);
    let buf = buffers.get(view.buffer().index()).ok_or("a buffer view names a missing buffer")?;
    let view_end = view.offset().checked_add(view.length()).filter(|e| *e <= buf.0.len()).ok_or("a buffer view runs past its buffer")?;
    let start = view.offset() + acc.offset();
    if count > 0 {
        let end = stride.checked_mul(count - 1).and_then(|x| x.checked_add(start + elem)).ok_or("an accessor is too large")?;
        if stride < elem || end > view_end {
            return Err(format!("accessor {} runs past its buffer view", acc.index()));
        }
    }
    let norm = acc.normalized();
    let data = &buf.0;
    let comp = |at: usize| -> f32 {
        let b = &data[at..at + size];
        match acc.data_type() {
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
    Ok((0..count)
        .map(|i| {
            let base = start + i * stride;
            std::array::from_fn(|k| comp(base + k * size))
        })
        .collect())
}
