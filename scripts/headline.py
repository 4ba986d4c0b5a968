#!/usr/bin/env python3
"""Write the README's headline table from the benchmarks' JSON in docs/benchmarks/.

    python3 scripts/headline.py [--readme README.md] [DIR]

One row per goal; each figure is read from the JSON that `scripts/bench-all` wrote (or an older
file where a benchmark was not in that run), with the machine and date that file names. The table
replaces the lines between the two marker comments in the README; the rest of the README is
left as it is. A figure a file lacks is written as "not measured". Only the standard library;
bad input gives one line on stderr and exit 2.
"""

import argparse
import json
import os
import re
import sys
import tempfile

BEGIN = "<!-- headline table: written by scripts/headline.py from docs/benchmarks/*.json -->"
END = "<!-- end of the headline table -->"


def dig(value, *keys):
    """The value at the first place the keys appear in order, each anywhere below the one before."""
    if not keys:
        return value
    if isinstance(value, dict):
        if keys[0] in value:
            found = dig(value[keys[0]], *keys[1:])
            if found is not None:
                return found
        for v in value.values():
            found = dig(v, *keys)
            if found is not None:
                return found
    elif isinstance(value, list):
        for v in value:
            found = dig(v, *keys)
            if found is not None:
                return found
    return None


def rows_where(value, key, want):
    """Every object below `value` whose `key` is `want`."""
    out = []
    if isinstance(value, dict):
        if value.get(key) == want:
            out.append(value)
        for v in value.values():
            out += rows_where(v, key, want)
    elif isinstance(value, list):
        for v in value:
            out += rows_where(v, key, want)
    return out


def num(x, digits=1):
    if x is None:
        return "not measured"
    if isinstance(x, (int, float)):
        if abs(x) >= 1000:
            return f"{x:,.0f}"
        return f"{x:.{digits}f}"
    return str(x)


def fps(ms):
    return f"{1000.0 / ms:.1f} fps" if isinstance(ms, (int, float)) and ms > 0 else "—"


def f_sim(d):
    a = [r.get("ms_per_tick_median") for r in rows_where(d, "trees", 100000)]
    b = [r.get("ms_per_tick_median") for r in rows_where(d, "trees", 1000000)]
    return f"{num(a[0] if a else None, 2)} / {num(b[0] if b else None, 1)} ms"


def f_raycast(d):
    ns = dig(d, "raycast", "ns_per_ray_median")
    return f"{ns / 1000:.2f} µs" if isinstance(ns, (int, float)) else "not measured"


def f_replay(d):
    return f"{num(dig(d, 'replay', 'wall_ms_median'))} ms, {num(dig(d, 'replay', 'speedup_median'))} × real time"


def f_study(d):
    return f"{num(dig(d, 'study', 'wall_seconds_median'), 3)} s"


def f_scale(d):
    runs = dig(d, "wall_s_runs") or []
    span = f" ({min(runs):.2f}–{max(runs):.2f})" if runs else ""
    return f"{num(dig(d, 'wall_s_median'), 2)} s{span}"


def f_wasm(d):
    sp = [v.get("speedup_median") for k, v in (dig(d, "wasm_replay") or {}).items() if k.startswith("module")]
    sp = [s for s in sp if isinstance(s, (int, float))]
    speed = f"{min(sp):,.0f}–{max(sp):,.0f} × real time" if sp else "not measured"
    gz = dig(d, "wasm_module", "gzipped_bytes")
    return f"replay {speed}; module {num(gz / 1000 if gz else None, 0)} kB gzipped"


def f_serve(d):
    live = dig(d, 'serve', 'live_verify_ms_p99')
    off = dig(d, 'serve_live_off', 'ack_ms_p99')
    return (f"{num(dig(d, 'serve', 'ack_ms_p50'), 2)} / {num(dig(d, 'serve', 'ack_ms_p99'), 2)} ms over "
            f"{num(dig(d, 'serve', 'seconds'), 0)} s"
            + (f" (live verification off: p99 {num(off, 2)} ms)" if off is not None else "")
            + (f"; a checkpoint verified live within {num(live / 1000, 2)} s (p99)" if live is not None else "")
            + f"; server CPU {num(dig(d, 'serve', 'server_cpu_percent'))} %, "
            f"{num(dig(d, 'serve', 'server_rss_mib_max'))} MiB")


def f_page(d):
    hundred = dig(d, "page_frame_100", "total_ms")
    more = f" / {num(hundred)} ms" if hundred is not None else ""
    return (f"{num(dig(d, 'page_frame', 'total_ms'))} ms{more} (p95 {num(dig(d, 'page_frame', 'total_ms_p95'))} ms"
            f"{' / ' + num(dig(d, 'page_frame_100', 'total_ms_p95')) + ' ms' if more else ''}); "
            f"page.js {num((dig(d, 'page_js_gzip_bytes') or 0) / 1000, 0)} kB gzipped")


def f_lsystem(d):
    r = rows_where(d, "n", 7)
    if not r:
        return "not measured"
    r = r[0]
    interp = r.get("interpret_ms_memo_2_threads", r.get("interpret_ms_memo"))
    return f"{num(r.get('derive_ms_2_threads'))} / {num(interp)} ms"


def f_frame(*keys):
    def f(d):
        ms = dig(d, *keys, "ms_per_frame")
        return f"{num(ms)} ms ({fps(ms)})" if isinstance(ms, (int, float)) else "not measured"
    return f


def f_park_shares(d):
    return f"{num(dig(d, 'grass_share_of_frame_percent'))} % / {num(dig(d, 'water_share_of_frame_percent'))} %"


def f_shells(d):
    v = dig(d, "fukuda_1km2_shells", "fps_drop_percent") or dig(d, "fukuda_1km2_shells_1280x720", "fps_drop_percent")
    return f"{num(v)} %"


def f_blades(d):
    v = dig(d, "goal_65536_visible_640x360", "ms_per_frame") or dig(d, "blades_65536_in_view_640x360", "ms_per_frame")
    return f"{num(v)} ms"


def f_play(*keys):
    def f(d):
        return f"{num(dig(d, *keys, 'fps'))} fps"
    return f


def f_aerial(d):
    g = dig(d, "ground_only", "fps") or dig(d, "ground", "fps")
    c = dig(d, "canopy", "fps")
    return f"{num(g)} / {num(c)} fps"


def f_segment(d):
    r = rows_where(d, "k", 3)
    s = (dig(r[0], "seconds", "segment") or r[0].get("segment_s")) if r else None
    return f"{num(s, 2)} s (k = 3)"


def f_video(d):
    return (f"{num(dig(d, 'video', 'wall_s'), 0)} s ({num(dig(d, 'video', 'frames_per_s'))} frames/s), "
            f"peak {num(dig(d, 'video', 'peak_rss_mib'), 0)} MiB")


def f_water(d):
    s = dig(d, "water_share_of_frame_percent")
    return f"{num(s)} % (lavapipe)"


def f_capacity(d):
    rows = [r for r in dig(d, "headset_capacity") or [] if r.get("kind") in ("billboard", "low-poly mesh")]
    if not rows:
        return "not measured"
    fit = min(r["trees_in_budget"] for r in rows)
    low = min(r["trees_in_budget_low"] for r in rows)
    mix = dig(d, "study_mix")
    of_mix = ""
    if mix:
        s = mix["shadows"]
        of_mix = f"; {mix['trees']} of the study's mix: {s['calls']} calls, {num(s['triangles'] / 1000, 0)} k triangles"
    return f"≥ {fit} trees of any one model ({low} without shadows){of_mix}"


def f_gpu(d):
    return f"{num(dig(d, 'reference_100_trees', 'mixed_shadows_on', 'fps'), 0)} fps"


# what, file, figure, goal
ROWS = [
    ("simulation tick, 100k / 1M trees", "sim.json", f_sim, "≤ 1.5 / ≤ 16 ms"),
    ("one controller ray, 10k trees and the study planes", "raycast.json", f_raycast, "≤ 2 µs"),
    ("replay of a 5-minute session, verified", "replay.json", f_replay, "≥ 20,000 ×"),
    ("the whole study (24 recordings, reports written)", "replay.json", f_study, "< 1 s"),
    ("1,000 recordings re-simulated and reported (`grove study`)", "scale.json", f_scale, "≤ 2 s"),
    ("the simulation as WebAssembly in Node: a 5-minute session replayed; the module's size", "wasm.json", f_wasm,
     "≥ 5,000 ×; ≤ 1,500 kB"),
    ("`grove serve`: 50 sessions at once on loopback, acknowledgement p50 / p99", "serve.json", f_serve, "p99 ≤ 20 ms; live ≤ 1 s"),
    ("the headset page's JavaScript per frame (steps, snapshot, three.js update), 9 / 100 trees, headless Chromium; "
     "its bundle", "page.json", f_page, "≤ 3 ms"),
    ("L-system bush 2, n = 7: derive (2 threads) / interpret (memoised)", "lsystem.json", f_lsystem, "≤ 60 / ≤ 40 ms"),
    ("reference scene, 100 trees, shadows, 1280 × 720", "render_reference.json",
     f_frame("reference_100_trees", "mixed_shadows_on"), "≥ 16.2 fps"),
    ("the same with the species bank's trees", "render_reference.json",
     f_frame("reference_100_trees", "species_shadows_on"), "≥ 16.2 fps"),
    ("forest, 10,106 species trees, shadows, 1280 × 720", "render_forest.json", f_frame("shadows_on"), "≥ 10 fps"),
    ("the park: grass, water and shadows, 1280 × 720", "park.json", f_frame("grass_water_shadows"), "≥ 30 fps"),
    ("the park's share of the frame taken by grass / by water", "park.json", f_park_shares, "≤ 25 % / ≤ 10 %"),
    ("Fukuda et al.'s 1 km² shell field, 1280 × 720: frame rate lost to the grass", "grass_goals.json", f_shells,
     "≤ 40 %"),
    ("65,536 grass blades in view, 640 × 360", "grass_goals.json", f_blades, "≤ 33 ms"),
    ("`grove play` window, 1280 × 720, `--quality auto`", "play.json", f_play("play_measure", "quality_auto"),
     "≥ 20 fps"),
    ("`grove play` of the park, `--quality full` (Xvfb)", "play.json", f_play("play_park", "quality_full"), "≥ 30 fps"),
    ("the headset page's trees of the study's models within Meta's WebXR budget (100 draw calls, 750 k triangles an "
     "eye), counted", "capacity.json", f_capacity, "≥ 100 trees"),
    ("aerial flight, 640 × 360: ground only / with the canopy", "aerial_bench.json", f_aerial, "≥ 15 fps"),
    ("aerial treetops of an 8192² pair (`grove aerial segment`)", "aerial_segment.json", f_segment, "≤ 1.5 s"),
    ("a 5-minute session as a 1280 × 720, 30 fps video", "video.json", f_video, "≤ 300 s"),
    ("water's share of the frame, Fukuda et al.'s water test", "water.json", f_water, "≤ 1 % on a GPU"),
    ("reference scene on a GPU (`grove bench render-gpu`)", "render_gpu.json", f_gpu, ""),
]


def fail(msg):
    print(f"headline: {msg}", file=sys.stderr)
    sys.exit(2)


def table(folder):
    lines = ["| what | figure | goal | machine, date |", "|---|---|---|---|"]
    runs = set()
    for what, file, fn, goal in ROWS:
        path = os.path.join(folder, file)
        try:
            with open(path) as f:
                d = json.load(f)
        except FileNotFoundError:
            lines.append(f"| {what} | not measured | {goal} | |")
            continue
        except (OSError, ValueError) as e:
            fail(f"{path}: {e}")
        machine = re.split(r",| \(", str(d.get("machine", "")))[0]
        when = d.get("date", "")
        if d.get("run"):
            runs.add(d["run"])
        lines.append(f"| {what} | {fn(d).replace('|', '/')} | {goal} | {machine}, {when} |")
    return lines, sorted(runs)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.error = lambda m: fail(m)
    ap.add_argument("--readme", default="README.md")
    ap.add_argument("folder", nargs="?", default="docs/benchmarks")
    a = ap.parse_args()
    try:
        with open(a.readme, encoding="utf-8") as f:
            text = f.read()
    except OSError as e:
        fail(f"{a.readme}: {e.strerror}")
    if text.count(BEGIN) != 1 or text.count(END) != 1 or text.index(BEGIN) > text.index(END):
        fail(f"{a.readme}: expected one pair of the headline table's marker comments")
    lines, runs = table(a.folder)
    head = [BEGIN, ""]
    if runs:
        head += ["From one run: " + "; ".join(runs) + ". Each benchmark's load average is in docs/benchmarks.md; on a",
                 "2-core machine without a GPU, frame times are lavapipe's (compare ratios within a run, not these", "absolute figures, against the goals).", ""]
    new = text[: text.index(BEGIN)] + "\n".join(head + lines) + "\n" + text[text.index(END):]
    fd, tmp = tempfile.mkstemp(dir=os.path.dirname(os.path.abspath(a.readme)), prefix=".headline-")
    with os.fdopen(fd, "w", encoding="utf-8") as f:
        f.write(new)
    os.replace(tmp, a.readme)


if __name__ == "__main__":
    main()
