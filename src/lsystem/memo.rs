//! The memoised turtle: for a deterministic grammar without parameters, what a symbol becomes
//! after k derivation steps always draws the same segments relative to the turtle that enters it.
//! Each such expansion is interpreted once, in the entering turtle's frame, and every occurrence
//! then costs one affine transform per segment instead of a walk over its symbols (mzucker's
//! "memoised" turtle does the same). It works from the grammar and n, without the derived string.
//!
//! Expansions are built level by level: level 0 is the symbol itself; level k walks the symbol's
//! successor with the level k − 1 expansions of its symbols. The top level walks the axiom's
//! successors (or the axiom) in world space and writes the segments, in parallel over the top
//! level's pieces, each into its own slice of the output.
//!
//! The segments equal the sequential turtle's (`turtle::interpret`) in order, depth, branch and
//! width, and in position up to rounding: the same rotations are composed in another order, so
//! positions differ by a few units in the last place of the tree's size (the tests state the
//! tolerance). Stochastic, conditional and parametric grammars, and successors with unbalanced
//! brackets, are not memoisable (`applies` says which).

use std::mem::MaybeUninit;

use glam::Vec3;
use rayon::prelude::*;

use super::error::LsystemError;
use super::grammar::{Choice, Grammar};
use super::turtle::{Segment, check_size};

/// A segment of an expansion, in the frame of the turtle that enters it.
#[derive(Clone, Copy, Debug)]
struct Local {
    /// Start, as coefficients of the entry frame's (H, L, U) from the entry position, metres.
    start: Vec3,
    /// End, the same way.
    end: Vec3,
    /// The width as a multiple of the entry width.
    width: f32,
    /// The bracket depth below the entry.
    depth: u32,
    /// 0: the entry's branch; otherwise the 1-based ordinal of the innermost `[` inside.
    branch: u32,
}

/// What one symbol becomes after some derivation steps, as the turtle sees it.
#[derive(Clone, Debug)]
struct Expansion {
    /// The segments it draws, in order.
    segs: Vec<Local>,
    /// The net move, in entry-frame coefficients, metres.
    offset: Vec3,
    /// The exit frame: H, L and U as coefficients of the entry frame.
    frame: [Vec3; 3],
    /// The net width factor.
    width: f32,
    /// The number of `[` inside.
    opens: u32,
}

/// The turtle's state while walking: position and frame in the walk's space.
#[derive(Clone, Copy)]
struct Walk {
    pos: Vec3,
    frame: [Vec3; 3],
    width: f32,
    branch: u32,
}

impl Walk {
    #[inline(always)]
    fn map(&self, c: Vec3) -> Vec3 {
        self.frame[0] * c.x + self.frame[1] * c.y + self.frame[2] * c.z
    }

    /// Where segment `s` of an expansion entered at this state lies; `depth` and `opens` are
    /// the walk's bracket depth and `[` count at the entry.
    #[inline(always)]
    fn place(&self, s: &Local, depth: u32, opens: u32) -> Local {
        Local {
            start: self.pos + self.map(s.start),
            end: self.pos + self.map(s.end),
            width: self.width * s.width,
            depth: depth + s.depth,
            branch: if s.branch == 0 { self.branch } else { opens + s.branch },
        }
    }

    /// The state after expansion `e`.
    #[inline(always)]
    fn after(&mut self, e: &Expansion) {
        self.pos += self.map(e.offset);
        self.frame = [self.map(e.frame[0]), self.map(e.frame[1]), self.map(e.frame[2])];
        self.width *= e.width;
    }
}

/// Whether the memoised turtle applies to `g`: every rule is the only one of its symbol, without
/// parameters or conditions, and every successor's brackets balance.
pub fn applies(g: &Grammar) -> bool {
    !g.is_parametric()
        && g.choice.iter().all(|c| matches!(c, Choice::Identity | Choice::Single(_)))
        && g.rules.iter().all(|r| balanced(&r.succ))
}

fn balanced(s: &[u8]) -> bool {
    let mut d = 0i64;
    for &c in s {
        d += (c == b'[') as i64 - (c == b']') as i64;
        if d < 0 {
            return false;
        }
    }
    d == 0
}

const IDENTITY: [Vec3; 3] = [Vec3::X, Vec3::Y, Vec3::Z];

/// Level 0: the symbol itself (the turtle commands of `turtle::apply`, without parameters).
fn base(sym: u8, g: &Grammar) -> Expansion {
    let (s, c) = g.angle_deg.to_radians().sin_cos();
    let mut e = Expansion { segs: Vec::new(), offset: Vec3::ZERO, frame: IDENTITY, width: 1.0, opens: 0 };
    // Rows: the new H, L, U in terms of the old; `turtle::rot(a, b, s, c)` turns a towards b.
    match sym {
        b'F' | b'f' => {
            e.offset = Vec3::new(g.step, 0.0, 0.0);
            if sym == b'F' {
                e.segs.push(Local { start: Vec3::ZERO, end: e.offset, width: 1.0, depth: 0, branch: 0 });
            }
        }
        b'+' => e.frame = [Vec3::new(c, s, 0.0), Vec3::new(-s, c, 0.0), Vec3::Z],
        b'-' => e.frame = [Vec3::new(c, -s, 0.0), Vec3::new(s, c, 0.0), Vec3::Z],
        b'&' => e.frame = [Vec3::new(c, 0.0, -s), Vec3::Y, Vec3::new(s, 0.0, c)],
        b'^' => e.frame = [Vec3::new(c, 0.0, s), Vec3::Y, Vec3::new(-s, 0.0, c)],
        b'\\' => e.frame = [Vec3::X, Vec3::new(0.0, c, s), Vec3::new(0.0, -s, c)],
        b'/' => e.frame = [Vec3::X, Vec3::new(0.0, c, -s), Vec3::new(0.0, s, c)],
        b'|' => e.frame = [Vec3::NEG_X, Vec3::NEG_Y, Vec3::Z],
        b'!' => e.width = g.width_factor,
        _ => {}
    }
    e
}

/// Walks `syms` (each with the expansion it stands for) from `start`, calling `emit` for every
/// segment; returns the end state, the `[` count, and fails on unbalanced brackets.
fn walk<'e>(
    syms: impl Iterator<Item = (u8, &'e Expansion)>,
    start: Walk,
    mut emit: impl FnMut(&Walk, &Expansion, u32, u32),
) -> Result<(Walk, u32), LsystemError> {
    let mut w = start;
    let mut stack: Vec<Walk> = Vec::new();
    let mut opens = 0u32;
    for (sym, e) in syms {
        match sym {
            b'[' => {
                stack.push(w);
                opens += 1;
                w.branch = opens;
            }
            b']' => {
                let Some(s) = stack.pop() else { return Err(LsystemError::UnbalancedClose) };
                w = s;
            }
            _ => {
                emit(&w, e, stack.len() as u32, opens);
                w.after(e);
                opens += e.opens;
            }
        }
    }
    if !stack.is_empty() {
        return Err(LsystemError::UnbalancedOpen(stack.len()));
    }
    Ok((w, opens))
}

/// The expansions of every symbol after `k` steps, from those after `k − 1` (`prev`); `None`
/// where a symbol has no rule (it stays its level-0 self).
fn next_level(
    g: &Grammar,
    bases: &[Expansion],
    prev: &[Option<Expansion>],
) -> Result<Vec<Option<Expansion>>, LsystemError> {
    let get = |c: u8| prev[c as usize].as_ref().unwrap_or(&bases[c as usize]);
    (0..128u8)
        .map(|sym| {
            let Choice::Single(r) = g.choice[sym as usize] else { return Ok(None) };
            let succ = &g.rules[r as usize].succ;
            let start = Walk { pos: Vec3::ZERO, frame: IDENTITY, width: 1.0, branch: 0 };
            let mut segs = Vec::new();
            let (end, opens) = walk(succ.iter().map(|&c| (c, get(c))), start, |w, e, d, o| {
                segs.extend(e.segs.iter().map(|s| w.place(s, d, o)));
            })?;
            Ok(Some(Expansion { segs, offset: end.pos, frame: end.frame, width: end.width, opens }))
        })
        .collect()
}

/// Interprets `g` derived `n` times, without deriving the string; fails with one line when the
/// grammar is not memoisable, the brackets do not balance, or the segments would need more than
/// `max_bytes`. Runs on the current rayon pool.
pub fn interpret_memo(g: &Grammar, n: u32, max_bytes: u64) -> Result<Vec<Segment>, LsystemError> {
    if !applies(g) {
        return Err(LsystemError::NotMemoisable);
    }
    let bases: Vec<Expansion> = (0..128u8).map(|c| base(c, g)).collect();
    // The top walk goes over the axiom's symbols each expanded n − 1 times, one step written out:
    // the pieces are the level n − 1 expansions.
    let mut level: Vec<Option<Expansion>> = vec![None; 128];
    for _ in 1..n {
        level = next_level(g, &bases, &level)?;
        let draws: u64 = level.iter().flatten().map(|e| e.segs.len() as u64).max().unwrap_or(0);
        check_size(draws, max_bytes)?;
    }
    let get = |c: u8| level[c as usize].as_ref().unwrap_or(&bases[c as usize]);
    let pieces: Vec<u8> = if n == 0 {
        g.axiom.clone()
    } else {
        g.axiom
            .iter()
            .flat_map(|&c| match g.choice[c as usize] {
                Choice::Single(r) => g.rules[r as usize].succ.clone(),
                _ => vec![c],
            })
            .collect()
    };
    // Pass 1 (sequential, one step per piece): the state at each piece and its output offset.
    let start = Walk { pos: Vec3::ZERO, frame: [Vec3::Y, Vec3::NEG_X, Vec3::Z], width: g.width, branch: 0 };
    let mut at: Vec<(Walk, u32, u32, u64)> = Vec::new();
    let mut total = 0u64;
    walk(pieces.iter().map(|&c| (c, get(c))), start, |w, e, d, o| {
        if !e.segs.is_empty() {
            at.push((*w, d, o, total));
            total += e.segs.len() as u64;
        }
    })?;
    check_size(total, max_bytes)?;
    // Pass 2 (parallel): each piece writes its own slice of the output. The output is written
    // once, without zeroing first, so its pages are first touched by the threads that fill them.
    let placed: Vec<&Expansion> = pieces.iter().map(|&c| get(c)).filter(|e| !e.segs.is_empty()).collect();
    let mut out: Vec<Segment> = Vec::with_capacity(total as usize);
    let mut slices: Vec<&mut [MaybeUninit<Segment>]> = Vec::with_capacity(placed.len());
    let mut rest = &mut out.spare_capacity_mut()[..total as usize];
    for e in &placed {
        let (a, b) = std::mem::take(&mut rest).split_at_mut(e.segs.len());
        slices.push(a);
        rest = b;
    }
    slices.into_par_iter().zip(placed.par_iter().zip(at.par_iter())).for_each(|(dst, (e, (w, d, o, _)))| {
        for (slot, s) in dst.iter_mut().zip(&e.segs) {
            let p = w.place(s, *d, *o);
            slot.write(Segment { start: p.start, end: p.end, width: p.width, depth: p.depth, branch: p.branch });
        }
    });
    // SAFETY: the slices cover the first `total` elements exactly (their lengths sum to `total`,
    // counted in pass 1), and every element of every slice was written above.
    unsafe { out.set_len(total as usize) };
    Ok(out)
}
