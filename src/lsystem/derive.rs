//! CPU derivation: every symbol's successor length, an exclusive scan for the write offsets, a
//! scatter of the successors; parallel with rayon over fixed chunks of the string.
//!
//! The scan is two-level: each chunk of `CHUNK` symbols sums its successor lengths (pass 1, in
//! parallel), the chunk sums are scanned (sequentially; there are few), and each chunk then
//! writes its successors from its offset with a running local offset (pass 2, in parallel), which
//! is the exclusive scan of the per-symbol lengths inside the chunk. Chunks are fixed in size and
//! every random choice depends only on the seed, the derivation step and the symbol's index, so
//! the result does not depend on the number of threads.
//!
//! Memory: one byte per symbol, and one `f32` per parameter in a side array (parameters of the
//! i-th symbol follow those of the symbols before it; a symbol's count is fixed by the grammar).

use rayon::prelude::*;

use super::error::LsystemError;
use super::grammar::{Choice, Grammar};

/// Symbols per chunk of the parallel passes (fixed, so the work split never changes results).
pub const CHUNK: usize = 1 << 16;

/// A derived string: a byte per symbol and the parameters in a side array.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LString {
    /// The symbols.
    pub syms: Vec<u8>,
    /// The parameters, in symbol order.
    pub params: Vec<f32>,
}

impl LString {
    /// A hash of the symbols and the parameters' bits (XXH3, 64 bits).
    pub fn hash(&self) -> u64 {
        let mut h = xxhash_rust::xxh3::Xxh3::new();
        h.update(&self.syms);
        for p in &self.params {
            h.update(&p.to_bits().to_le_bytes());
        }
        h.digest()
    }

    /// The number of symbols.
    pub fn len(&self) -> usize {
        self.syms.len()
    }

    /// Whether the string is empty.
    pub fn is_empty(&self) -> bool {
        self.syms.is_empty()
    }

    /// The count of each symbol (indexed by its byte).
    pub fn counts(&self) -> [u64; 128] {
        let parts: Vec<[u64; 128]> = self
            .syms
            .par_chunks(CHUNK)
            .map(|c| {
                let mut n = [0u64; 128];
                for &s in c {
                    n[(s & 127) as usize] += 1;
                }
                n
            })
            .collect();
        let mut n = [0u64; 128];
        for p in parts {
            for (a, b) in n.iter_mut().zip(p) {
                *a += b;
            }
        }
        n
    }

    /// The string in ABOP notation, e.g. `F(1.5)[+F(0.9)]`.
    pub fn to_text(&self, g: &Grammar) -> String {
        let mut s = String::new();
        let mut p = 0;
        for &c in &self.syms {
            s.push(c as char);
            let a = g.arity[c as usize] as usize;
            if a > 0 {
                let args: Vec<String> = self.params[p..p + a].iter().map(|v| format!("{v}")).collect();
                s.push_str(&format!("({})", args.join(",")));
                p += a;
            }
        }
        s
    }
}

/// Limits a derivation may not pass; passing one stops it with one clear line.
#[derive(Clone, Copy, Debug)]
pub struct Limits {
    /// Most symbols in a derived string.
    pub max_symbols: u64,
    /// Most bytes of a derived string (symbols plus parameters).
    pub max_bytes: u64,
}

impl Default for Limits {
    fn default() -> Limits {
        Limits { max_symbols: 1 << 30, max_bytes: 2 << 30 }
    }
}

impl Limits {
    /// Fails with one line when a string of `symbols` symbols and `params` parameters is too big.
    pub fn check(&self, step: u32, symbols: u64, params: u64) -> Result<(), LsystemError> {
        let bytes = symbols + 4 * params;
        if symbols > self.max_symbols || symbols > u32::MAX as u64 {
            return Err(LsystemError::TooManySymbols { step, symbols, limit: self.max_symbols.min(u32::MAX as u64) });
        }
        if bytes > self.max_bytes {
            return Err(LsystemError::DeriveBytes { step, bytes, limit: self.max_bytes });
        }
        Ok(())
    }
}

/// A 32-bit integer hash (the same on the CPU and in the GPU shader).
pub fn mix32(mut x: u32) -> u32 {
    x ^= x >> 16;
    x = x.wrapping_mul(0x7feb_352d);
    x ^= x >> 15;
    x = x.wrapping_mul(0x846c_a68b);
    x ^= x >> 16;
    x
}

/// The random key of derivation step `step` (1-based) for `seed`.
pub fn step_key(seed: u64, step: u32) -> u32 {
    mix32(step.wrapping_mul(0x9e37_79b9) ^ mix32(seed as u32 ^ mix32((seed >> 32) as u32)))
}

/// The 24-bit random number of the symbol at `index` in a step with `key`.
pub fn draw(key: u32, index: u32) -> u32 {
    mix32(index ^ key) >> 8
}

/// Which rule rewrites symbol `s` at `index`, given its parameters; `None` keeps it.
#[inline]
fn pick(g: &Grammar, s: u8, index: u32, key: u32, args: &[f32]) -> Option<u32> {
    match &g.choice[(s & 127) as usize] {
        Choice::Identity => None,
        Choice::Single(r) => Some(*r),
        Choice::Stochastic(t) => {
            let h = draw(key, index);
            let mut k = 0;
            while k + 1 < t.len() && h >= t[k].0 {
                k += 1;
            }
            Some(t[k].1)
        }
        Choice::Conditional(rs) => {
            rs.iter().copied().find(|&r| g.rules[r as usize].cond.as_ref().is_none_or(|c| c.eval(args) != 0.0))
        }
    }
}

/// The number of parameters of the successor of rule `r`.
fn succ_params(g: &Grammar, r: u32) -> usize {
    g.rules[r as usize].args.len()
}

/// Per chunk: (output symbols, output parameters, input parameters).
fn chunk_sizes(g: &Grammar, syms: &[u8], params: &[f32], base: usize, param_base: usize, key: u32) -> (u64, u64, u64) {
    let (mut n, mut np, mut p) = (0u64, 0u64, param_base);
    for (i, &s) in syms.iter().enumerate() {
        let a = g.arity[(s & 127) as usize] as usize;
        match pick(g, s, (base + i) as u32, key, &params[p..p + a]) {
            Some(r) => {
                n += g.rules[r as usize].succ.len() as u64;
                np += succ_params(g, r) as u64;
            }
            None => {
                n += 1;
                np += a as u64;
            }
        }
        p += a;
    }
    (n, np, (p - param_base) as u64)
}

/// One derivation step (`step` is 1-based) of `s`.
pub fn step(g: &Grammar, s: &LString, step: u32, seed: u64, limits: &Limits) -> Result<LString, LsystemError> {
    let key = step_key(seed, step);
    let parametric = g.is_parametric();
    // Input parameter offsets of the chunks (only needed with parameters).
    let in_param_counts: Vec<u64> = if parametric {
        s.syms.par_chunks(CHUNK).map(|c| c.iter().map(|&x| g.arity[(x & 127) as usize] as u64).sum()).collect()
    } else {
        vec![0; s.syms.len().div_ceil(CHUNK)]
    };
    let in_param_base = exclusive_scan(&in_param_counts);
    // Pass 1: the successor lengths, summed per chunk.
    let sizes: Vec<(u64, u64, u64)> = s
        .syms
        .par_chunks(CHUNK)
        .enumerate()
        .map(|(c, chunk)| chunk_sizes(g, chunk, &s.params, c * CHUNK, in_param_base[c] as usize, key))
        .collect();
    let out_syms = exclusive_scan(&sizes.iter().map(|x| x.0).collect::<Vec<_>>());
    let out_params = exclusive_scan(&sizes.iter().map(|x| x.1).collect::<Vec<_>>());
    let total = out_syms.last().copied().unwrap_or(0) + sizes.last().map(|x| x.0).unwrap_or(0);
    let total_params = out_params.last().copied().unwrap_or(0) + sizes.last().map(|x| x.1).unwrap_or(0);
    limits.check(step, total, total_params)?;

    // Pass 2: every chunk scatters its successors into its own slice of the output.
    let mut syms = vec![0u8; total as usize];
    let mut params = vec![0f32; total_params as usize];
    let mut sym_parts: Vec<&mut [u8]> = Vec::with_capacity(sizes.len());
    let mut par_parts: Vec<&mut [f32]> = Vec::with_capacity(sizes.len());
    let (mut rest_s, mut rest_p) = (syms.as_mut_slice(), params.as_mut_slice());
    for sz in &sizes {
        let (a, b) = std::mem::take(&mut rest_s).split_at_mut(sz.0 as usize);
        sym_parts.push(a);
        rest_s = b;
        let (a, b) = std::mem::take(&mut rest_p).split_at_mut(sz.1 as usize);
        par_parts.push(a);
        rest_p = b;
    }
    s.syms.par_chunks(CHUNK).zip(sym_parts.into_par_iter().zip(par_parts)).enumerate().for_each(
        |(c, (chunk, (out, pout)))| {
            let base = c * CHUNK;
            let (mut o, mut po, mut p) = (0usize, 0usize, in_param_base[c] as usize);
            for (i, &x) in chunk.iter().enumerate() {
                let a = g.arity[(x & 127) as usize] as usize;
                let args = &s.params[p..p + a];
                match pick(g, x, (base + i) as u32, key, args) {
                    Some(r) => {
                        let rule = &g.rules[r as usize];
                        out[o..o + rule.succ.len()].copy_from_slice(&rule.succ);
                        o += rule.succ.len();
                        for e in &rule.args {
                            pout[po] = e.eval(args);
                            po += 1;
                        }
                    }
                    None => {
                        out[o] = x;
                        o += 1;
                        pout[po..po + a].copy_from_slice(args);
                        po += a;
                    }
                }
                p += a;
            }
        },
    );
    Ok(LString { syms, params })
}

/// The exclusive prefix sums of `v`.
pub fn exclusive_scan(v: &[u64]) -> Vec<u64> {
    let mut acc = 0;
    v.iter()
        .map(|x| {
            let r = acc;
            acc += x;
            r
        })
        .collect()
}

/// The axiom as a string.
pub fn axiom(g: &Grammar) -> LString {
    LString { syms: g.axiom.clone(), params: g.axiom_params.clone() }
}

/// Derives `n` steps from the axiom on the current rayon pool.
pub fn derive(g: &Grammar, n: u32, seed: u64, limits: &Limits) -> Result<LString, LsystemError> {
    let mut s = axiom(g);
    limits.check(0, s.len() as u64, s.params.len() as u64)?;
    for k in 1..=n {
        s = step(g, &s, k, seed, limits)?;
    }
    Ok(s)
}

/// Derives on a pool of `threads` threads.
pub fn derive_threads(
    g: &Grammar,
    n: u32,
    seed: u64,
    limits: &Limits,
    threads: usize,
) -> Result<LString, LsystemError> {
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().map_err(LsystemError::ThreadPool)?;
    pool.install(|| derive(g, n, seed, limits))
}
