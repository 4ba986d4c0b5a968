//! Tiny glTF files built in tests: a buffer of little-endian numbers, embedded as base64 or
//! written beside the file, and the JSON around it.

#![allow(dead_code)]

/// Standard base64 with padding.
pub fn base64(bytes: &[u8]) -> String {
    const A: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::new();
    for c in bytes.chunks(3) {
        let n = (c[0] as u32) << 16 | (*c.get(1).unwrap_or(&0) as u32) << 8 | *c.get(2).unwrap_or(&0) as u32;
        for k in 0..4 {
            if k <= c.len() {
                out.push(A[(n >> (18 - 6 * k) & 63) as usize] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}

/// Little-endian bytes of floats.
pub fn f32s(v: &[f32]) -> Vec<u8> {
    v.iter().flat_map(|x| x.to_le_bytes()).collect()
}

/// Little-endian bytes of u16s, padded to 4 bytes.
pub fn u16s(v: &[u16]) -> Vec<u8> {
    let mut b: Vec<u8> = v.iter().flat_map(|x| x.to_le_bytes()).collect();
    while b.len() % 4 != 0 {
        b.push(0);
    }
    b
}

/// A buffer being filled with views: returns each view's JSON as it is added.
#[derive(Default)]
pub struct Buffer {
    pub bytes: Vec<u8>,
    pub views: Vec<String>,
}

impl Buffer {
    /// Adds a view of `data` (padded to 4 bytes) and returns its index.
    pub fn view(&mut self, data: &[u8]) -> usize {
        let offset = self.bytes.len();
        self.bytes.extend_from_slice(data);
        while self.bytes.len() % 4 != 0 {
            self.bytes.push(0);
        }
        self.views.push(format!(r#"{{"buffer":0,"byteOffset":{offset},"byteLength":{}}}"#, data.len()));
        self.views.len() - 1
    }

    /// The `buffers` and `bufferViews` members, the buffer embedded as a data URI.
    pub fn json_embedded(&self) -> String {
        format!(
            r#""buffers":[{{"uri":"data:application/octet-stream;base64,{}","byteLength":{}}}],"bufferViews":[{}]"#,
            base64(&self.bytes),
            self.bytes.len(),
            self.views.join(",")
        )
    }
}

/// A float accessor of `n` elements of `ty` (`VEC3`, …) over view `view`.
pub fn float_accessor(view: usize, n: usize, ty: &str) -> String {
    format!(r#"{{"bufferView":{view},"componentType":5126,"count":{n},"type":"{ty}"}}"#)
}

/// A u16 index accessor of `n` indices over view `view`.
pub fn index_accessor(view: usize, n: usize) -> String {
    format!(r#"{{"bufferView":{view},"componentType":5123,"count":{n},"type":"SCALAR"}}"#)
}

/// A POSITION accessor over view `view` of `p` (x, y, z triples), with the min and max glTF
/// requires.
pub fn position_accessor(view: usize, p: &[f32]) -> String {
    let (mut lo, mut hi) = ([f32::MAX; 3], [f32::MIN; 3]);
    for q in p.chunks_exact(3) {
        for k in 0..3 {
            lo[k] = lo[k].min(q[k]);
            hi[k] = hi[k].max(q[k]);
        }
    }
    format!(
        r#"{{"bufferView":{view},"componentType":5126,"count":{},"type":"VEC3","min":{lo:?},"max":{hi:?}}}"#,
        p.len() / 3
    )
}
