//! The toroidal update: which texels of a level are newly exposed when its window moves, and
//! where they go in the level's texture.
//!
//! A level's window of `size × size` texels starting at mip texel `origin` stores mip texel
//! `(u, v)` at texture texel `(u mod size, v mod size)`. When the window moves by `(dx, dy)`
//! texels (both under `size`), only the strip of `|dx|` columns and the strip of `|dy|` rows
//! that entered it are new: `|dx| · size + |dy| · (size − |dx|)` texels, the corner counted once.
//! A strip may straddle the texture's edge; [`wrap`] splits it there so each piece is a plain
//! rectangle of the texture.

use glam::IVec2;

use super::LevelPlacement;

/// A rectangle of texels in one mip's texel coordinates (x east, y south).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct TexelRect {
    /// First column.
    pub x: i32,
    /// First row.
    pub y: i32,
    /// Columns.
    pub w: u32,
    /// Rows.
    pub h: u32,
}

impl TexelRect {
    /// The rectangle's texel count.
    pub fn area(&self) -> u64 {
        self.w as u64 * self.h as u64
    }

    /// The part shared with `other`, if any.
    pub fn intersect(&self, other: &TexelRect) -> Option<TexelRect> {
        let x0 = self.x.max(other.x);
        let y0 = self.y.max(other.y);
        let x1 = (self.x as i64 + self.w as i64).min(other.x as i64 + other.w as i64);
        let y1 = (self.y as i64 + self.h as i64).min(other.y as i64 + other.h as i64);
        (x1 > x0 as i64 && y1 > y0 as i64).then(|| TexelRect {
            x: x0,
            y: y0,
            w: (x1 - x0 as i64) as u32,
            h: (y1 - y0 as i64) as u32,
        })
    }
}

/// A level's window as a rectangle of its mip.
pub fn window(p: &LevelPlacement, size: u32) -> TexelRect {
    TexelRect { x: p.origin.x, y: p.origin.y, w: size, h: size }
}

/// The texels of `new`'s window that `old`'s did not hold: the whole window when there was no
/// old one, the mip changed, or it moved by a full window or more; else a column strip (full
/// height) and a row strip (without the column strip's part).
pub fn exposed(old: Option<&LevelPlacement>, new: &LevelPlacement, size: u32) -> Vec<TexelRect> {
    let n = size as i64;
    let full = vec![window(new, size)];
    let Some(old) = old else { return full };
    let d = new.origin.as_i64vec2() - old.origin.as_i64vec2();
    if old.mip != new.mip || d.x.abs() >= n || d.y.abs() >= n {
        return full;
    }
    let mut out = Vec::with_capacity(2);
    let (nx, ny) = (new.origin.x as i64, new.origin.y as i64);
    // The columns that entered, over the whole new height.
    if d.x != 0 {
        let x = if d.x > 0 { nx + n - d.x } else { nx };
        out.push(TexelRect { x: x as i32, y: ny as i32, w: d.x.unsigned_abs() as u32, h: size });
    }
    // The rows that entered, over the columns the old window shared.
    if d.y != 0 {
        let x = if d.x < 0 { nx - d.x } else { nx };
        let y = if d.y > 0 { ny + n - d.y } else { ny };
        let w = (n - d.x.abs()) as u32;
        if w > 0 {
            out.push(TexelRect { x: x as i32, y: y as i32, w, h: d.y.unsigned_abs() as u32 });
        }
    }
    out
}

/// One plain rectangle of a level's texture and the mip texels it receives.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Piece {
    /// The first texture texel, each coordinate in `0..size`.
    pub tex: IVec2,
    /// The mip texels, `tex + (w, h) <= size` in the texture.
    pub src: TexelRect,
}

/// Splits a rectangle of at most `size × size` mip texels at the texture's wrap: one to four
/// pieces.
pub fn wrap(rect: &TexelRect, size: u32) -> Vec<Piece> {
    let n = size as i64;
    let split = |start: i32, len: u32| -> Vec<(i64, i64, u32)> {
        let t = (start as i64).rem_euclid(n);
        let first = (len as i64).min(n - t);
        let mut v = vec![(t, start as i64, first as u32)];
        if (len as i64) > first {
            v.push((0, start as i64 + first, (len as i64 - first) as u32));
        }
        v
    };
    let mut out = Vec::with_capacity(4);
    for &(ty, sy, h) in &split(rect.y, rect.h) {
        for &(tx, sx, w) in &split(rect.x, rect.w) {
            out.push(Piece {
                tex: IVec2::new(tx as i32, ty as i32),
                src: TexelRect { x: sx as i32, y: sy as i32, w, h },
            });
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(mip: u32, x: i32, y: i32) -> LevelPlacement {
        LevelPlacement { mip, origin: IVec2::new(x, y) }
    }

    /// A simulated level texture: which mip texel each texture texel holds.
    struct Texture {
        n: usize,
        held: Vec<Option<(i32, i32)>>,
        written: u64,
    }

    impl Texture {
        fn apply(&mut self, rects: &[TexelRect]) {
            for r in rects {
                for p in wrap(r, self.n as u32) {
                    assert!(
                        p.tex.x >= 0
                            && p.tex.y >= 0
                            && p.tex.x as u32 + p.src.w <= self.n as u32
                            && p.tex.y as u32 + p.src.h <= self.n as u32
                    );
                    for j in 0..p.src.h as i32 {
                        for i in 0..p.src.w as i32 {
                            let k = (p.tex.y + j) as usize * self.n + (p.tex.x + i) as usize;
                            self.held[k] = Some((p.src.x + i, p.src.y + j));
                            self.written += 1;
                        }
                    }
                }
            }
        }

        /// Every texel of the window is where toroidal addressing puts it.
        fn check(&self, w: &LevelPlacement) {
            let n = self.n as i32;
            for v in w.origin.y..w.origin.y + n {
                for u in w.origin.x..w.origin.x + n {
                    let k = v.rem_euclid(n) as usize * self.n + u.rem_euclid(n) as usize;
                    assert_eq!(self.held[k], Some((u, v)), "texel ({u}, {v}) of the window at {}", w.origin);
                }
            }
        }
    }

    #[test]
    fn a_move_uploads_exactly_the_exposed_strips() {
        let n = 16u32;
        let mut tex = Texture { n: n as usize, held: vec![None; (n * n) as usize], written: 0 };
        let mut cur = at(0, -5, 7);
        tex.apply(&exposed(None, &cur, n));
        assert_eq!(tex.written, 256);
        tex.check(&cur);
        // (dx, dy) and the texels a move must write: |dx|·16 + |dy|·(16 − |dx|).
        let moves = [
            (3, 0, 48),
            (0, 2, 32),
            (-4, 0, 64),
            (5, -3, 80 + 33),
            (-7, 6, 112 + 54),
            (0, 0, 0),
            (15, 15, 240 + 15),
            (-20, 1, 256),
            (11, -9, 176 + 45),
        ];
        for (dx, dy, texels) in moves {
            let next = at(0, cur.origin.x + dx, cur.origin.y + dy);
            let rects = exposed(Some(&cur), &next, n);
            let area: u64 = rects.iter().map(TexelRect::area).sum();
            assert_eq!(area, texels, "move ({dx}, {dy})");
            tex.written = 0;
            tex.apply(&rects);
            assert_eq!(tex.written, texels, "the wrapped pieces write each texel once");
            tex.check(&next);
            cur = next;
        }
        // A new mip rewrites the whole window.
        assert_eq!(
            exposed(Some(&cur), &at(1, cur.origin.x, cur.origin.y), n).iter().map(TexelRect::area).sum::<u64>(),
            256
        );
    }

    #[test]
    fn wrap_splits_a_rectangle_at_the_texture_edges() {
        let pieces = wrap(&TexelRect { x: 14, y: -1, w: 4, h: 3 }, 16);
        assert_eq!(
            pieces,
            [
                Piece { tex: IVec2::new(14, 15), src: TexelRect { x: 14, y: -1, w: 2, h: 1 } },
                Piece { tex: IVec2::new(0, 15), src: TexelRect { x: 16, y: -1, w: 2, h: 1 } },
                Piece { tex: IVec2::new(14, 0), src: TexelRect { x: 14, y: 0, w: 2, h: 2 } },
                Piece { tex: IVec2::new(0, 0), src: TexelRect { x: 16, y: 0, w: 2, h: 2 } },
            ]
        );
        assert_eq!(wrap(&TexelRect { x: 32, y: 16, w: 16, h: 16 }, 16).len(), 1, "an aligned window is one piece");
    }
}
