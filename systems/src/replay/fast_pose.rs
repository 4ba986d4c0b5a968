//! The controller-pose event line read without serde, when it has exactly the shape the
//! recorder writes:
//!
//! ```text
//! {"type":"event","tick":T,"ms":M,"frame":F,"event":{"kind":"controller_pose","pose":{"position":[x,y,z],"rotation":[x,y,z,w]}}}
//! ```
//!
//! Pose lines are most of a recording, and reading them through serde's generic machinery was
//! the larger part of a replay's parsing. Anything else (other spacing, field order, escapes,
//! numbers this reader does not take) returns `None`, and the line is read by serde as before.
//!
//! A number is taken only where serde_json computes it exactly: at most 15 significant digits
//! and a decimal exponent of at most 22 either way, so the digits as an integer and the power
//! of ten are both exact in `f64`, and the one division or multiplication that serde_json makes
//! rounds once, here as there. The value then becomes an `f32` as serde makes it (`as f32`).

use glam::{Quat, Vec3};

use super::EventLine;
use crate::components::Pose;
use crate::input::InputEvent;

/// The powers of ten that are exact in `f64`.
const POW10: [f64; 23] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20,
    1e21, 1e22,
];

/// The powers of ten up to 10^8, as integers.
const POW10_U64: [u64; 9] = [1, 10, 100, 1_000, 10_000, 100_000, 1_000_000, 10_000_000, 100_000_000];

/// The powers of ten up to 10^15, as integers.
const POW10_U64_16: [u64; 16] = {
    let mut t = [1u64; 16];
    let mut i = 1;
    while i < 16 {
        t[i] = t[i - 1] * 10;
        i += 1;
    }
    t
};

/// The eight bytes of `s` from `at`, read little-endian, zeros (not digits) past its end.
#[inline(always)]
fn eight_bytes(s: &[u8], at: usize) -> u64 {
    match s.get(at..at + 8) {
        Some(b) => u64::from_le_bytes(b.try_into().unwrap_or_default()),
        None => {
            let mut b = [0u8; 8];
            let tail = s.get(at..).unwrap_or_default();
            b[..tail.len()].copy_from_slice(tail);
            u64::from_le_bytes(b)
        }
    }
}

/// Eight bytes read little-endian (the first byte lowest): how many of them, from the first,
/// are ASCII digits, and the value of those digits as a decimal integer (0 for none).
#[inline(always)]
fn eight_digits(chunk: u64) -> (usize, u64) {
    const LOW7: u64 = 0x7f7f_7f7f_7f7f_7f7f;
    const HIGH: u64 = 0x8080_8080_8080_8080;
    // Each byte less `'0'` (by xor, which is the same on the bytes 0x30..=0x39 and maps every
    // other byte above 9): a digit's byte becomes its value.
    let d = chunk ^ 0x3030_3030_3030_3030;
    // The high bit of each byte that is not a digit: above 9 in its low seven bits (adding
    // 0x76 reaches 0x80; no byte carries into the next), or with its own high bit set.
    let not_digit = (((d & LOW7) + 0x7676_7676_7676_7676) | d) & HIGH;
    let n = (not_digit.trailing_zeros() / 8) as usize;
    if n == 0 {
        return (0, 0);
    }
    // The n digits moved to the top bytes, zeros before them: the same number.
    let v = d << (8 * (8 - n));
    // Pairs, then fours, then all eight: each byte's digit the more significant of its pair.
    let v = (v & 0x0f0f_0f0f_0f0f_0f0f).wrapping_mul(10).wrapping_add(v >> 8) & 0x00ff_00ff_00ff_00ff;
    let v = (v.wrapping_mul(100).wrapping_add(v >> 16)) & 0x0000_ffff_0000_ffff;
    let v = v.wrapping_mul(10_000).wrapping_add(v >> 32) & 0xffff_ffff;
    (n, v)
}

/// A cursor over a line's bytes (also [`super::fast_checkpoint`]'s).
pub(super) struct Cursor<'a> {
    pub(super) s: &'a [u8],
    pub(super) at: usize,
}

impl<'a> Cursor<'a> {
    /// The literal text `l`.
    pub(super) fn lit(&mut self, l: &str) -> Option<()> {
        let end = self.at.checked_add(l.len())?;
        (self.s.get(self.at..end)? == l.as_bytes()).then(|| self.at = end)
    }

    /// A JSON integer without sign, fraction or exponent: `0` or digits not starting with 0.
    pub(super) fn uint(&mut self) -> Option<u64> {
        let start = self.at;
        let mut v: u64 = 0;
        while let Some(&b) = self.s.get(self.at).filter(|b| b.is_ascii_digit()) {
            v = v.checked_mul(10)?.checked_add(u64::from(b - b'0'))?;
            self.at += 1;
        }
        let n = self.at - start;
        (n == 1 || (n > 1 && self.s[start] != b'0')).then_some(v)
    }

    /// One byte.
    pub(super) fn byte(&mut self, b: u8) -> Option<()> {
        (self.s.get(self.at) == Some(&b)).then(|| self.at += 1)
    }

    /// The run of digits at the cursor: its length, and its value when it has at most 19
    /// digits (which cannot overflow `u64`) on top of `start` × 10^length. The cursor moves past it.
    fn digits(&mut self, start: u64) -> (usize, Option<u64>) {
        let from = self.at;
        let mut v = start;
        while let Some(&b) = self.s.get(self.at) {
            let d = b.wrapping_sub(b'0');
            if d > 9 {
                break;
            }
            v = v.wrapping_mul(10).wrapping_add(u64::from(d));
            self.at += 1;
        }
        let run = self.at - from;
        (run, (run <= 19).then_some(v))
    }

    /// A JSON number that serde_json computes exactly (see the module's text), computed as it
    /// computes it: the digits as an integer, then one multiplication or division by a power
    /// of ten.
    fn number(&mut self) -> Option<f32> {
        /// The digits as an integer stay below this: at most 15 significant digits.
        const SIGNIFICAND_END: u64 = 1_000_000_000_000_000;
        let negative = self.byte(b'-').is_some();
        if let Some((significand, exponent)) = self.one_digit_and_fraction() {
            let f = significand as i64 as f64 / POW10[exponent];
            return Some(if negative { -f } else { f } as f32);
        }
        let int_start = self.at;
        let (int_digits, significand) = self.digits(0);
        let significand = significand.filter(|&v| v < SIGNIFICAND_END)?;
        if int_digits == 0 || (int_digits > 1 && self.s[int_start] == b'0') {
            return None;
        }
        let mut exponent = 0i32;
        let mut significand = significand;
        if self.byte(b'.').is_some() {
            // After a zero integer part, the fraction's leading zeros add nothing to the value.
            let mut zeros = 0;
            if significand == 0 {
                while self.s.get(self.at) == Some(&b'0') {
                    self.at += 1;
                    zeros += 1;
                }
            }
            let (rest, v) = self.digits(significand);
            let frac_digits = zeros + rest;
            // With a non-zero integer part, more than 19 digits in all are more than 15
            // significant ones (and could overflow `u64`).
            let v = v?;
            if frac_digits == 0 || (significand > 0 && int_digits + rest > 19) || v >= SIGNIFICAND_END {
                return None;
            }
            significand = v;
            exponent = -(frac_digits as i32);
        }
        if matches!(self.s.get(self.at), Some(b'e' | b'E')) {
            self.at += 1;
            let sign = match self.s.get(self.at) {
                Some(b'-') => {
                    self.at += 1;
                    -1
                }
                Some(b'+') => {
                    self.at += 1;
                    1
                }
                _ => 1,
            };
            let (e_digits, e) = self.digits(0);
            if e_digits == 0 || e_digits > 3 {
                return None;
            }
            exponent += sign * e? as i32;
        }
        let pow = *POW10.get(exponent.unsigned_abs() as usize)?;
        // Below 10^15, so exact through `i64` (one conversion instruction, where `u64` takes a few).
        let f = significand as i64 as f64;
        let f = if exponent >= 0 { f * pow } else { f / pow };
        Some(if negative { -f } else { f } as f32)
    }

    /// The shape of nearly every number the recorder writes: one integer digit, a point, and
    /// 1 to 15 fraction digits, and no exponent after them. Its digits as an integer and their
    /// count after the point, read eight at a time, where [`Cursor::number`]'s general reading
    /// gives the same significand (then below 10^15) and exponent; `None` (the cursor unmoved)
    /// for anything else.
    #[inline(always)]
    fn one_digit_and_fraction(&mut self) -> Option<(u64, usize)> {
        /// The digits as an integer stay below this: at most 15 significant digits.
        const SIGNIFICAND_END: u64 = 1_000_000_000_000_000;
        let s = self.s.get(self.at..)?;
        let int = s.first()?.wrapping_sub(b'0');
        if int > 9 || s.get(1) != Some(&b'.') {
            return None;
        }
        let (n, first) = eight_digits(eight_bytes(s, 2));
        let (digits, value) = if n < 8 {
            (n, first)
        } else {
            let (m, second) = eight_digits(eight_bytes(s, 10));
            (8 + m, first * POW10_U64[m] + second)
        };
        // At most 15 digits after the point (not 16 or more), followed by no exponent.
        if digits == 0 || digits > 15 || matches!(s.get(2 + digits), Some(b'e' | b'E')) {
            return None;
        }
        // Leading zeros of the fraction, skipped by the general reading after a zero integer
        // part, add nothing to the integer; with a non-zero one, 1 + 15 digits stay within 19.
        let significand = u64::from(int) * POW10_U64_16[digits] + value;
        if significand >= SIGNIFICAND_END {
            return None;
        }
        self.at += 2 + digits;
        Some((significand, digits))
    }

    fn numbers<const N: usize>(&mut self) -> Option<[f32; N]> {
        self.byte(b'[')?;
        let mut out = [0.0; N];
        for (i, x) in out.iter_mut().enumerate() {
            if i > 0 {
                self.byte(b',')?;
            }
            *x = self.number()?;
        }
        self.byte(b']')?;
        Some(out)
    }
}

/// The event line, if `body` (a line without its `sum` field) is a controller pose written in
/// the recorder's own shape; `None` otherwise, for serde to read.
pub(super) fn read(body: &str) -> Option<EventLine> {
    let mut c = Cursor { s: body.as_bytes(), at: 0 };
    c.lit("{\"type\":\"event\",\"tick\":")?;
    let tick = c.uint()?;
    c.lit(",\"ms\":")?;
    let ms = c.uint()?;
    c.lit(",\"frame\":")?;
    let frame = c.uint()?;
    c.lit(",\"event\":{\"kind\":\"controller_pose\",\"pose\":{\"position\":")?;
    let [px, py, pz] = c.numbers::<3>()?;
    c.lit(",\"rotation\":")?;
    let [rx, ry, rz, rw] = c.numbers::<4>()?;
    c.lit("}}}")?;
    if c.at != body.len() {
        return None;
    }
    let pose = Pose { position: Vec3::new(px, py, pz), rotation: Quat::from_xyzw(rx, ry, rz, rw) };
    Some(EventLine { tick, ms, frame, event: InputEvent::ControllerPose { pose } })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// What serde reads from the same body (the reader's path before this one).
    fn by_serde(body: &str) -> Option<EventLine> {
        match serde_json::from_str::<super::super::Line>(body).ok()? {
            super::super::Line::Event(e) => Some(e),
            _ => None,
        }
    }

    fn bits(e: &EventLine) -> (u64, u64, u64, [u32; 7]) {
        let InputEvent::ControllerPose { pose } = &e.event else { panic!("a pose") };
        let p = pose.position.to_array();
        let r = pose.rotation.to_array();
        (e.tick, e.ms, e.frame, [p[0], p[1], p[2], r[0], r[1], r[2], r[3]].map(f32::to_bits))
    }

    fn line(position: &str, rotation: &str) -> String {
        format!(
            "{{\"type\":\"event\",\"tick\":187,\"ms\":3117,\"frame\":187,\"event\":{{\"kind\":\"controller_pose\",\"pose\":{{\"position\":[{position}],\"rotation\":[{rotation}]}}}}}}"
        )
    }

    #[test]
    fn a_pose_line_reads_to_the_same_bits_as_through_serde() {
        // Numbers as the recorder writes them, and others within this reader's exact range.
        let cases = [
            ("0.25,1.3167496,5.743838", "-0.05938796,0.00004282934,0.0000025480444,0.998235"),
            ("-0,0,1e-7", "0.1,0.2,0.3,0.9"),
            ("123456789012345,-1.5E3,2.5e+2", "1e-22,-3.4028235e20,0.000000000000000000001,1"),
            ("0.000001,100000000,-0.0", "0.7071068,0,0,0.7071068"),
        ];
        for (p, r) in cases {
            let body = line(p, r);
            let fast = read(&body).unwrap_or_else(|| panic!("read: {body}"));
            let slow = by_serde(&body).expect("serde reads it");
            assert_eq!(bits(&fast), bits(&slow), "{body}");
        }
        // Random f32 values written as serde writes them read back to the same bits.
        let (mut x, mut read_here) = (99u32, 0);
        for _ in 0..20_000 {
            let mut v = [0f32; 7];
            for f in &mut v {
                x = x.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
                let exp = (x >> 27) as i32 - 16;
                *f = ((x & 0xffff) as f32 / 65536.0 - 0.5) * libm::scalbnf(1.0, exp);
            }
            let j = |s: &[f32]| s.iter().map(|f| serde_json::to_string(f).unwrap()).collect::<Vec<_>>().join(",");
            let body = line(&j(&v[..3]), &j(&v[3..]));
            if let Some(fast) = read(&body) {
                assert_eq!(bits(&fast), bits(&by_serde(&body).unwrap()), "{body}");
                read_here += 1;
            }
        }
        // Shortest f32 texts have at most 9 digits: nearly all are read here, not by serde.
        assert!(read_here > 19_000, "{read_here} of 20000 read without serde");
    }

    #[test]
    fn eight_bytes_at_once_give_the_digits_one_at_a_time_give() {
        let one_at_a_time = |bytes: [u8; 8]| {
            let n = bytes.iter().take_while(|b| b.is_ascii_digit()).count();
            (n, bytes[..n].iter().fold(0u64, |v, b| v * 10 + u64::from(b - b'0')))
        };
        // Every byte value at every place, among digits and after a run of them.
        for place in 0..8 {
            for b in 0..=255u8 {
                let mut bytes = *b"12345678";
                bytes[place] = b;
                assert_eq!(eight_digits(u64::from_le_bytes(bytes)), one_at_a_time(bytes), "{bytes:?}");
            }
        }
        // Random runs of digits cut by random bytes.
        let mut x = 7u64;
        for _ in 0..100_000 {
            x = x.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
            let mut bytes = [0u8; 8];
            for (i, b) in bytes.iter_mut().enumerate() {
                let r = (x >> (8 * i)) as u8;
                *b = if r % 8 == 0 { r } else { b'0' + r % 10 };
            }
            assert_eq!(eight_digits(u64::from_le_bytes(bytes)), one_at_a_time(bytes), "{bytes:?}");
        }
        assert_eq!(eight_digits(u64::from_le_bytes(*b"99999999")), (8, 99_999_999));
        assert_eq!(eight_digits(u64::from_le_bytes(*b"00000000")), (8, 0));
        assert_eq!(eight_digits(u64::from_le_bytes(*b"0123,]}}")), (4, 123));
    }

    #[test]
    fn anything_but_the_recorders_own_shape_is_left_to_serde() {
        let good = line("1,2,3", "0,0,0,1");
        assert!(read(&good).is_some());
        for bad in [
            good.replace("\"tick\":187", "\"tick\": 187"),
            good.replace("\"tick\":187", "\"tick\":0187"),
            good.replace("\"tick\":187", "\"tick\":1.5"),
            good.replace("[1,2,3]", "[1,2]"),
            good.replace("[1,2,3]", "[1,2,3,4]"),
            good.replace("[1,2,3]", "[1.,2,3]"),
            good.replace("[1,2,3]", "[01,2,3]"),
            good.replace("[1,2,3]", "[1e400,2,3]"),
            good.replace("[1,2,3]", "[1234567890123456,2,3]"),
            good.replace("[1,2,3]", "[1e23,2,3]"),
            good.replace("[1,2,3]", "[NaN,2,3]"),
            good.replace("}}}", "}}"),
            format!("{good} "),
            good.replace("controller_pose", "head_pose"),
        ] {
            assert!(read(&bad).is_none(), "{bad}");
        }
    }
}
