// L-system derivation on the GPU (see src/lsystem/gpu.rs): successor lengths, a hierarchical
// exclusive scan and a scatter. Symbols are bytes packed four to a u32, little-endian.
//
// `table` holds, for each of the 128 symbols, [first alternative, alternative count] (count 0:
// the symbol stays), then three words per alternative [threshold, pool byte offset, length], then
// the successor pool (bytes packed like the symbols) from word `prm.pool`.

struct Params {
    // Input symbols (lengths, scatter) or elements to scan (scan_block, add_offsets).
    n: u32,
    // The derivation step's random key.
    key: u32,
    // Threads per row of a two-dimensional dispatch.
    row: u32,
    // Word offset of the successor pool in `table`.
    pool: u32,
}

@group(0) @binding(0) var<uniform> prm: Params;
@group(0) @binding(1) var<storage, read> src: array<u32>;
@group(0) @binding(2) var<storage, read> table: array<u32>;
@group(0) @binding(3) var<storage, read_write> lens: array<u32>;
@group(0) @binding(4) var<storage, read_write> sums: array<u32>;
@group(0) @binding(5) var<storage, read_write> dst: array<atomic<u32>>;

const WG: u32 = 256u;
const IDENTITY: u32 = 0xffffffffu;

// The same 32-bit hash as `derive::mix32`.
fn mix32(x0: u32) -> u32 {
    var x = x0;
    x ^= x >> 16u;
    x *= 0x7feb352du;
    x ^= x >> 15u;
    x *= 0x846ca68bu;
    x ^= x >> 16u;
    return x;
}

fn sym_at(i: u32) -> u32 {
    return (src[i >> 2u] >> ((i & 3u) * 8u)) & 0x7fu;
}

// The chosen successor of symbol `s` at index `i`: (pool byte offset or IDENTITY, length).
fn choose(s: u32, i: u32) -> vec2<u32> {
    let count = table[2u * s + 1u];
    if count == 0u {
        return vec2<u32>(IDENTITY, 1u);
    }
    let a0 = 256u + 3u * table[2u * s];
    var k = 0u;
    if count > 1u {
        let h = mix32(i ^ prm.key) >> 8u;
        loop {
            if k + 1u >= count || h < table[a0 + 3u * k] {
                break;
            }
            k += 1u;
        }
    }
    return vec2<u32>(table[a0 + 3u * k + 1u], table[a0 + 3u * k + 2u]);
}

// Successor lengths, summed per input word (four symbols).
@compute @workgroup_size(256)
fn lengths(@builtin(global_invocation_id) gid: vec3<u32>) {
    let w = gid.x + gid.y * prm.row;
    let words = (prm.n + 3u) / 4u;
    if w >= words {
        return;
    }
    var total = 0u;
    for (var b = 0u; b < 4u; b += 1u) {
        let i = 4u * w + b;
        if i < prm.n {
            total += choose(sym_at(i), i).y;
        }
    }
    lens[w] = total;
}

var<workgroup> tmp: array<u32, 256>;

// An exclusive scan of each block of 256 elements of `lens`, in place; the block's total goes
// to `sums`.
@compute @workgroup_size(256)
fn scan_block(@builtin(local_invocation_id) lid: vec3<u32>, @builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let block = wid.x + wid.y * nwg.x;
    let blocks = (prm.n + WG - 1u) / WG;
    if block >= blocks {
        return;
    }
    let i = block * WG + lid.x;
    var v = 0u;
    if i < prm.n {
        v = lens[i];
    }
    tmp[lid.x] = v;
    workgroupBarrier();
    for (var off = 1u; off < WG; off *= 2u) {
        var add = 0u;
        if lid.x >= off {
            add = tmp[lid.x - off];
        }
        workgroupBarrier();
        tmp[lid.x] += add;
        workgroupBarrier();
    }
    if i < prm.n {
        lens[i] = tmp[lid.x] - v;
    }
    if lid.x == WG - 1u {
        sums[block] = tmp[WG - 1u];
    }
}

// Adds each block's scanned offset to its elements.
@compute @workgroup_size(256)
fn add_offsets(@builtin(local_invocation_id) lid: vec3<u32>, @builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let block = wid.x + wid.y * nwg.x;
    let i = block * WG + lid.x;
    if i < prm.n {
        lens[i] += sums[block];
    }
}

// Writes every symbol's successor at its offset. A thread owns a contiguous byte range and ORs
// whole words into the zeroed output; only the words at its range's ends are shared.
@compute @workgroup_size(256)
fn scatter(@builtin(global_invocation_id) gid: vec3<u32>) {
    let w = gid.x + gid.y * prm.row;
    let words = (prm.n + 3u) / 4u;
    if w >= words {
        return;
    }
    var off = lens[w];
    var cur = off >> 2u;
    var acc = 0u;
    for (var b = 0u; b < 4u; b += 1u) {
        let i = 4u * w + b;
        if i >= prm.n {
            break;
        }
        let s = sym_at(i);
        let c = choose(s, i);
        for (var k = 0u; k < c.y; k += 1u) {
            var byte = s;
            if c.x != IDENTITY {
                let q = c.x + k;
                byte = (table[prm.pool + (q >> 2u)] >> ((q & 3u) * 8u)) & 0xffu;
            }
            let wi = off >> 2u;
            if wi != cur {
                atomicOr(&dst[cur], acc);
                acc = 0u;
                cur = wi;
            }
            acc |= byte << ((off & 3u) * 8u);
            off += 1u;
        }
    }
    if acc != 0u {
        atomicOr(&dst[cur], acc);
    }
}
