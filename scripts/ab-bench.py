#!/usr/bin/env python3
"""Old and new builds of grove in turn (A B A B): `grove bench WHICH` run PAIRS times in each of two
checkouts that hold a release build (target/release/grove), timing every run's CPU (user and
system of the process and all its threads, from the kernel's accounting) and wall clock.

    python3 scripts/ab-bench.py study 12 /path/to/old /path/to/new [--json OUT]

Prints each pair and the per-pair ratio medians (new over old) of the CPU time and of the
benchmark's own figure where it has one (study: wall_seconds_median; replay: wall_ms_median).
The CPU time holds better than wall time on a machine with other work on it (docs/codemap.md)."""
import argparse, json, os, resource, statistics, subprocess, sys, time


def fail(msg):
    print(f"ab-bench: {msg}", file=sys.stderr)
    sys.exit(2)

OWN = {"study": ("study", "wall_seconds_median"), "replay": ("replay", "wall_ms_median")}


def run(checkout, which):
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.monotonic()
    out = subprocess.run([os.path.join(checkout, "target/release/grove"), "bench", which], cwd=checkout, capture_output=True)
    wall = time.monotonic() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if out.returncode != 0:
        fail(f"grove bench {which} in {checkout} failed: {out.stderr.decode(errors='replace').strip()[-300:]}")
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return {"cpu_s": cpu, "wall_s": wall, "load": os.getloadavg()[0], "json": json.loads(out.stdout)}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("which")
    ap.add_argument("pairs", type=int)
    ap.add_argument("old")
    ap.add_argument("new")
    ap.add_argument("--json", help="write every run here")
    a = ap.parse_args()
    for d in (a.old, a.new):
        if not os.access(os.path.join(d, "target/release/grove"), os.X_OK):
            fail(f"{d} has no target/release/grove (build it with cargo build --release there)")
    if a.pairs < 1:
        fail("at least one pair")
    rows = []
    for i in range(a.pairs):
        old, new = run(a.old, a.which), run(a.new, a.which)
        rows.append({"old": old, "new": new})
        print(f"{i + 1}: cpu {old['cpu_s']:.2f} s / {new['cpu_s']:.2f} s, ratio {new['cpu_s'] / old['cpu_s']:.3f}, load {new['load']:.1f}", flush=True)
    print(f"cpu ratio median (new / old): {statistics.median(r['new']['cpu_s'] / r['old']['cpu_s'] for r in rows):.3f}")
    if a.which in OWN:
        k, f = OWN[a.which]
        print(f"{k}.{f} ratio median: {statistics.median(r['new']['json'][k][f] / r['old']['json'][k][f] for r in rows):.3f}")
    if a.json:
        with open(a.json + ".tmp", "w") as fh:
            json.dump(rows, fh, indent=1)
        os.replace(a.json + ".tmp", a.json)


if __name__ == "__main__":
    main()
