//! The 3D turtle: reads a derived string and gives the segments that `F` draws.
//!
//! Commands (ABOP notation; δ is the grammar's angle, a parameter replaces it or the step):
//! `F`/`F(l)` draw forward, `f`/`f(l)` move forward, `+ -` turn left/right about U, `& ^` pitch
//! down/up about L, `\ /` roll left/right about H, `|` turn around, `!` multiply the width by the
//! width factor (`!(w)` sets it), `[ ]` push and pop the state. Other letters do nothing.
//! The turtle starts at the origin heading up: H = +Y, L = −X, U = +Z (metres, right-handed).
//!
//! `interpret` is the plain sequential turtle. `interpret_parallel` finds every bracket's match
//! with a chunked scan, then walks the branches in parallel, each from the state at its `[`,
//! skipping nested branches (which other walks take). Every symbol's state goes through the same
//! operations in the same order as in the sequential turtle, so the segments are bit-identical.

use glam::Vec3;
use rayon::prelude::*;

use super::derive::{CHUNK, LString, exclusive_scan};
use super::error::LsystemError;
use super::grammar::Grammar;

/// A drawn segment.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Segment {
    /// Start point, metres.
    pub start: Vec3,
    /// End point, metres.
    pub end: Vec3,
    /// Width (diameter) of the line, metres.
    pub width: f32,
    /// Bracket depth of the `F` that drew it (0 on the main axis).
    pub depth: u32,
    /// The branch: 1 + the ordinal of the innermost enclosing `[`, 0 on the main axis.
    pub branch: u32,
}

/// The turtle's state.
#[derive(Clone, Copy, Debug)]
pub struct State {
    /// Position, metres.
    pub pos: Vec3,
    /// Heading.
    pub h: Vec3,
    /// Left.
    pub l: Vec3,
    /// Up.
    pub u: Vec3,
    /// Line width, metres.
    pub width: f32,
}

/// The grammar's turtle settings, with the default angle's sine and cosine.
#[derive(Clone, Copy, Debug)]
pub struct Config {
    /// Step, metres.
    pub step: f32,
    /// Width factor of `!`.
    pub width_factor: f32,
    /// Initial width.
    pub width: f32,
    sin: f32,
    cos: f32,
}

impl Config {
    /// The settings of grammar `g`.
    pub fn of(g: &Grammar) -> Config {
        let (sin, cos) = g.angle_deg.to_radians().sin_cos();
        Config { step: g.step, width_factor: g.width_factor, width: g.width, sin, cos }
    }

    /// The starting state.
    pub fn start(&self) -> State {
        State { pos: Vec3::ZERO, h: Vec3::Y, l: Vec3::NEG_X, u: Vec3::Z, width: self.width }
    }
}

/// Rotates the pair (a, b) by the angle with sine `s` and cosine `c`: a towards b.
#[inline]
fn rot(a: &mut Vec3, b: &mut Vec3, s: f32, c: f32) {
    let na = *a * c + *b * s;
    let nb = *b * c - *a * s;
    *a = na;
    *b = nb;
}

/// Applies symbol `sym` with parameters `args` (other than brackets) to `t`; returns the end
/// point when it draws.
#[inline(always)]
pub fn apply(t: &mut State, sym: u8, args: &[f32], cfg: &Config) -> Option<Vec3> {
    let (s, c) = match args.first() {
        Some(a) if matches!(sym, b'+' | b'-' | b'&' | b'^' | b'\\' | b'/') => a.to_radians().sin_cos(),
        _ => (cfg.sin, cfg.cos),
    };
    match sym {
        b'F' | b'f' => {
            let len = args.first().copied().unwrap_or(cfg.step);
            t.pos += t.h * len;
            (sym == b'F').then_some(t.pos)
        }
        b'+' => {
            rot(&mut t.h, &mut t.l, s, c);
            None
        }
        b'-' => {
            rot(&mut t.h, &mut t.l, -s, c);
            None
        }
        b'&' => {
            rot(&mut t.h, &mut t.u, -s, c);
            None
        }
        b'^' => {
            rot(&mut t.h, &mut t.u, s, c);
            None
        }
        b'\\' => {
            rot(&mut t.l, &mut t.u, s, c);
            None
        }
        b'/' => {
            rot(&mut t.l, &mut t.u, -s, c);
            None
        }
        b'|' => {
            t.h = -t.h;
            t.l = -t.l;
            None
        }
        b'!' => {
            t.width = match args.first() {
                Some(w) => *w,
                None => t.width * cfg.width_factor,
            };
            None
        }
        _ => None,
    }
}

/// Fails with one line when the segments of `draws` `F`s would need more than `max_bytes`.
pub fn check_size(draws: u64, max_bytes: u64) -> Result<(), LsystemError> {
    let bytes = draws * std::mem::size_of::<Segment>() as u64;
    if bytes > max_bytes {
        return Err(LsystemError::InterpretBytes { bytes, draws, limit: max_bytes });
    }
    Ok(())
}

/// The plain sequential turtle.
pub fn interpret(s: &LString, g: &Grammar) -> Result<Vec<Segment>, LsystemError> {
    let cfg = Config::of(g);
    let mut t = cfg.start();
    let mut stack: Vec<(State, u32)> = Vec::new();
    let draws = s.syms.iter().filter(|&&c| c == b'F').count();
    let mut segs = Vec::with_capacity(draws);
    // Without parameters every symbol's argument list is empty: skip the slicing.
    let parametric = g.is_parametric();
    let (mut p, mut opens, mut branch) = (0usize, 0u32, 0u32);
    for &sym in &s.syms {
        match sym {
            b'[' => {
                stack.push((t, branch));
                opens += 1;
                branch = opens;
            }
            b']' => {
                let Some((st, b)) = stack.pop() else { return Err(LsystemError::UnbalancedClose) };
                t = st;
                branch = b;
            }
            _ => {
                let a = if parametric { g.arity[(sym & 127) as usize] as usize } else { 0 };
                let start = t.pos;
                let args = if parametric { &s.params[p..p + a] } else { &[] };
                if let Some(end) = apply(&mut t, sym, args, &cfg) {
                    segs.push(Segment { start, end, width: t.width, depth: stack.len() as u32, branch });
                }
                p += a;
            }
        }
    }
    if !stack.is_empty() {
        return Err(LsystemError::UnbalancedOpen(stack.len()));
    }
    Ok(segs)
}

/// What a walk needs to know at a `[`: where its `]` is and the counts just after it.
#[derive(Clone, Copy, Default)]
struct Match {
    close: u32,
    draws: u32,
    params: u32,
    opens: u32,
}

/// Running counts at a position: drawn `F`s, parameters and `[`s before it.
#[derive(Clone, Copy, Default)]
struct Counts {
    draws: u32,
    params: u32,
    opens: u32,
}

struct Ctx<'a> {
    s: &'a LString,
    g: &'a Grammar,
    cfg: Config,
    matches: Vec<Match>,
    out: *mut Segment,
    parametric: bool,
}

// The raw output pointer is written at disjoint indices (each `F` has its own), so sharing the
// context between threads is sound.
unsafe impl Sync for Ctx<'_> {}

/// A branch to walk: from `start` (after its `[`) to `end` (its `]` or the string's end).
#[derive(Clone, Copy)]
struct Task {
    start: usize,
    end: usize,
    state: State,
    counts: Counts,
    depth: u32,
    branch: u32,
}

/// Branches longer than this many symbols are walked as separate rayon tasks.
const SPAWN_MIN: usize = 1 << 14;

fn walk<'s>(scope: &rayon::Scope<'s>, ctx: &'s Ctx<'s>, first: Task) {
    let mut pending = vec![first];
    while let Some(task) = pending.pop() {
        let Task { start, end, mut state, counts, depth, branch } = task;
        let (mut draws, mut p, mut opens) = (counts.draws as usize, counts.params as usize, counts.opens as usize);
        let mut i = start;
        while i < end {
            let sym = ctx.s.syms[i];
            if sym == b'[' {
                let m = ctx.matches[opens];
                let child = Task {
                    start: i + 1,
                    end: m.close as usize,
                    state,
                    counts: Counts { draws: draws as u32, params: p as u32, opens: opens as u32 + 1 },
                    depth: depth + 1,
                    branch: opens as u32 + 1,
                };
                if child.end - child.start >= SPAWN_MIN {
                    scope.spawn(move |sc| walk(sc, ctx, child));
                } else {
                    pending.push(child);
                }
                i = m.close as usize + 1;
                draws = m.draws as usize;
                p = m.params as usize;
                opens = m.opens as usize;
                continue;
            }
            let a = if ctx.parametric { ctx.g.arity[(sym & 127) as usize] as usize } else { 0 };
            let from = state.pos;
            let args = if ctx.parametric { &ctx.s.params[p..p + a] } else { &[] };
            if let Some(to) = apply(&mut state, sym, args, &ctx.cfg) {
                // SAFETY: `draws` is this `F`'s ordinal among all drawn symbols, below the
                // capacity reserved for them, and no other walk visits this `F`.
                unsafe {
                    ctx.out.add(draws).write(Segment { start: from, end: to, width: state.width, depth, branch })
                };
                draws += 1;
            }
            p += a;
            i += 1;
        }
    }
}

/// The parallel turtle on the current rayon pool; equal to `interpret`.
pub fn interpret_parallel(s: &LString, g: &Grammar, max_bytes: u64) -> Result<Vec<Segment>, LsystemError> {
    let cfg = Config::of(g);
    // Pass 1: per chunk, the counts of drawn symbols, parameters and opening brackets.
    let per_chunk: Vec<Counts> = s
        .syms
        .par_chunks(CHUNK)
        .map(|c| {
            let mut k = Counts::default();
            for &x in c {
                k.draws += (x == b'F') as u32;
                k.params += g.arity[(x & 127) as usize] as u32;
                k.opens += (x == b'[') as u32;
            }
            k
        })
        .collect();
    let draw_base = exclusive_scan(&per_chunk.iter().map(|k| k.draws as u64).collect::<Vec<_>>());
    let param_base = exclusive_scan(&per_chunk.iter().map(|k| k.params as u64).collect::<Vec<_>>());
    let open_base = exclusive_scan(&per_chunk.iter().map(|k| k.opens as u64).collect::<Vec<_>>());
    let total_draws: u64 = per_chunk.iter().map(|k| k.draws as u64).sum();
    let total_opens: u64 = per_chunk.iter().map(|k| k.opens as u64).sum();
    check_size(total_draws, max_bytes)?;

    // Pass 2: brackets matched inside each chunk; unmatched ones are resolved in order below.
    let mut matches = vec![Match::default(); total_opens as usize];
    let mut parts: Vec<&mut [Match]> = Vec::with_capacity(per_chunk.len());
    let mut rest = matches.as_mut_slice();
    for k in &per_chunk {
        let (a, b) = std::mem::take(&mut rest).split_at_mut(k.opens as usize);
        parts.push(a);
        rest = b;
    }
    type Loose = (Vec<(u32, Match)>, Vec<u32>);
    let loose: Vec<Loose> = s
        .syms
        .par_chunks(CHUNK)
        .zip(parts)
        .enumerate()
        .map(|(c, (chunk, part))| {
            let base = c * CHUNK;
            let mut k = Counts { draws: draw_base[c] as u32, params: param_base[c] as u32, opens: open_base[c] as u32 };
            let local0 = k.opens;
            let mut stack: Vec<u32> = Vec::new();
            let mut closes: Vec<(u32, Match)> = Vec::new();
            for (i, &x) in chunk.iter().enumerate() {
                k.draws += (x == b'F') as u32;
                k.params += g.arity[(x & 127) as usize] as u32;
                if x == b'[' {
                    stack.push(k.opens);
                    k.opens += 1;
                } else if x == b']' {
                    let m = Match { close: (base + i) as u32, draws: k.draws, params: k.params, opens: k.opens };
                    match stack.pop() {
                        Some(o) => part[(o - local0) as usize] = m,
                        None => closes.push(((base + i) as u32, m)),
                    }
                }
            }
            (closes, stack)
        })
        .collect();
    let mut stack: Vec<u32> = Vec::new();
    for (closes, opens) in loose {
        for (_, m) in closes {
            let Some(o) = stack.pop() else { return Err(LsystemError::UnbalancedClose) };
            matches[o as usize] = m;
        }
        stack.extend(opens);
    }
    if !stack.is_empty() {
        return Err(LsystemError::UnbalancedOpen(stack.len()));
    }

    // Pass 3: walk the branches.
    let mut out: Vec<Segment> = Vec::with_capacity(total_draws as usize);
    let ctx = Ctx { s, g, cfg, matches, out: out.as_mut_ptr(), parametric: g.is_parametric() };
    let root = Task { start: 0, end: s.syms.len(), state: cfg.start(), counts: Counts::default(), depth: 0, branch: 0 };
    rayon::scope(|sc| walk(sc, &ctx, root));
    // SAFETY: every drawn symbol wrote its segment at its own ordinal, and there are
    // `total_draws` of them.
    unsafe { out.set_len(total_draws as usize) };
    Ok(out)
}
