#!/usr/bin/env python3
"""Run a grove study on a Ray cluster: one Ray task per shard, then `grove study merge`.

Each task runs the grove binary on its shard (`grove study --shard K/N`) and returns the partial
result's bytes through Ray; the driver writes them beside each other and merges them into the
same reports a run without shards writes. Tasks share nothing but the binary and their input:

  recordings already on every node (a shared or copied folder):
    ray_study.py --grove target/release/grove --replays replays/study --shards 8 --out reports

  synthetic participants made by each task from a seed (nothing to copy but the binary):
    ray_study.py --grove grove --synth-participants 500 --shards 8 --out reports
    ray_study.py --grove grove --synth-participants 500 --synth-set snap_threshold=0.2 --shards 8 --out reports

The second form writes each shard's recordings into a task-local temporary folder
(`grove synth --shard K/N`), studies them there and drops them; with --synth-set it also
synthesises the baseline participants and compares (re-simulated participants).
docs/scale.md explains the options, the figures and a cluster run.
"""

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time


def fail(message):
    print(f"ray_study: {message}", file=sys.stderr)
    sys.exit(2)


def parse_args(argv):
    ap = argparse.ArgumentParser(description="Run grove study shards as Ray tasks, then merge them.")
    ap.add_argument("--grove", default="grove", help="the grove binary, at the same path on every node (default: grove on PATH)")
    ap.add_argument("--replays", help="the folder of recordings, readable at the same path on every node")
    ap.add_argument("--baseline", help="the baseline recordings of a re-simulated-participants what-if")
    ap.add_argument("--set", action="append", default=[], metavar="NAME=VALUE[,VALUE...]", help="a what-if or sweep on the replayed hands, as for grove study --set")
    ap.add_argument("--synth-participants", type=int, metavar="P", help="instead of --replays: each task synthesises its shard of P participants")
    ap.add_argument("--synth-seed", type=int, default=2019, help="the seed of grove synth (default 2019)")
    ap.add_argument("--synth-set", action="append", default=[], metavar="NAME=VALUE", help="with --synth-participants: re-simulated participants under this setting, compared with the baseline participants")
    ap.add_argument("--shards", type=int, required=True, metavar="N", help="the number of shards (Ray tasks)")
    ap.add_argument("--out", required=True, help="the folder of the merged reports")
    ap.add_argument("--parts", help="keep the partial results in this folder (default: a temporary folder, removed)")
    ap.add_argument("--address", help="the Ray cluster to join (default: start a local one)")
    ap.add_argument("--num-cpus", type=int, help="CPUs of the local Ray cluster (default: all)")
    ap.add_argument("--threads-per-task", type=int, default=1, help="CPUs each task asks Ray for and grove's threads in it (default 1)")
    ap.add_argument("--timings", help="write the per-shard and total seconds to this JSON file")
    ap.add_argument("--force", action="store_true", help="replace the reports of an earlier run in --out")
    ap.add_argument("--json", action="store_true", help="print the merged summary as JSON")
    a = ap.parse_args(argv)
    if (a.replays is None) == (a.synth_participants is None):
        fail("give either --replays DIR or --synth-participants P")
    if a.synth_set and a.synth_participants is None:
        fail("--synth-set needs --synth-participants")
    if a.baseline and a.replays is None:
        fail("--baseline goes with --replays")
    if a.shards < 1:
        fail(f"--shards {a.shards}: at least 1")
    if a.threads_per_task < 1:
        fail(f"--threads-per-task {a.threads_per_task}: at least 1")
    for name, folder in (("--replays", a.replays), ("--baseline", a.baseline)):
        if folder is not None and not os.path.isdir(folder):
            fail(f"{name} {folder}: no such folder")
    # Refuse what the merge would refuse before the shards run, not after.
    reports = ("trial_results.csv", "trees.csv", "summary.json", "ablation.png", "sweep.csv", "sweep.png")
    if not a.force and any(os.path.exists(os.path.join(a.out, r)) for r in reports):
        fail(f"{a.out}: holds the reports of an earlier run; use --force to replace them, or another --out")
    return a


def run_grove(grove, args, env):
    """Runs grove; returns its exit code, or raises with its one-line error for bad input."""
    p = subprocess.run([grove, *args], env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    if p.returncode not in (0, 1):
        err = p.stderr.strip().splitlines()
        raise RuntimeError(f"grove {' '.join(args[:1])} failed (exit {p.returncode}): {err[-1] if err else 'no message'}")
    return p.returncode


def shard_task(k, opts):
    """One shard: (k, partial result bytes, seconds, grove's exit code). Runs on a Ray worker."""
    start = time.monotonic()
    env = dict(os.environ, RAYON_NUM_THREADS=str(opts["threads"]))
    n = opts["shards"]
    with tempfile.TemporaryDirectory(prefix=f"grove-shard-{k}-") as tmp:
        part = os.path.join(tmp, "part")
        study = ["study", "--shard", f"{k}/{n}", "--out", part]
        for s in opts["set"]:
            study += ["--set", s]
        if opts["synth"] is None:
            study += ["--replays", opts["replays"]]
            if opts["baseline"]:
                study += ["--baseline", opts["baseline"]]
        else:
            participants, seed, synth_set = opts["synth"]
            base = os.path.join(tmp, "baseline")
            synth = ["synth", "--participants", str(participants), "--seed", str(seed), "--shard", f"{k}/{n}"]
            run_grove(opts["grove"], synth + ["--out", base], env)
            if synth_set:
                what_if = os.path.join(tmp, "what-if")
                run_grove(opts["grove"], synth + ["--out", what_if] + [x for s in synth_set for x in ("--set", s)], env)
                study += ["--replays", what_if, "--baseline", base]
            else:
                study += ["--replays", base]
        code = run_grove(opts["grove"], study, env)
        with open(part, "rb") as f:
            data = f.read()
    return k, data, time.monotonic() - start, code


def main(argv):
    a = parse_args(argv)
    grove = shutil.which(a.grove) if os.sep not in a.grove else os.path.abspath(a.grove)
    if grove is None or not os.path.isfile(grove):
        fail(f"{a.grove}: no grove binary there (give its path with --grove)")
    try:
        import ray
    except ImportError:
        fail("the Python package ray is missing: pip install ray (scripts/test installs it into target/pyenv)")
    opts = {
        "grove": grove,
        "shards": a.shards,
        "set": a.set,
        "threads": a.threads_per_task,
        "replays": os.path.abspath(a.replays) if a.replays else None,
        "baseline": os.path.abspath(a.baseline) if a.baseline else None,
        "synth": (a.synth_participants, a.synth_seed, a.synth_set) if a.synth_participants is not None else None,
    }
    t0 = time.monotonic()
    if a.address:
        ray.init(address=a.address, log_to_driver=False)
    else:
        ray.init(num_cpus=a.num_cpus, include_dashboard=False, log_to_driver=False)
    t_init = time.monotonic() - t0
    task = ray.remote(num_cpus=a.threads_per_task, max_retries=2)(shard_task)
    t1 = time.monotonic()
    pending = [task.remote(k, opts) for k in range(1, a.shards + 1)]
    try:
        results = ray.get(pending)
    except Exception as e:  # a task's error arrives wrapped; keep its last line
        lines = [l for l in str(e).strip().splitlines() if l.strip()]
        ray.shutdown()
        fail(lines[-1] if lines else "a shard failed")
    t_shards = time.monotonic() - t1
    ray.shutdown()

    parts_dir = a.parts or tempfile.mkdtemp(prefix="grove-parts-")
    os.makedirs(parts_dir, exist_ok=True)
    paths = []
    for k, data, _, _ in sorted(results):
        path = os.path.join(parts_dir, f"part-{k:05}-of-{a.shards}")
        with open(path + ".tmp", "wb") as f:
            f.write(data)
        os.replace(path + ".tmp", path)
        paths.append(path)
    t2 = time.monotonic()
    merge = [grove, "study", "merge", *paths, "--out", a.out] + (["--force"] if a.force else []) + (["--json"] if a.json else [])
    code = subprocess.run(merge).returncode
    t_merge = time.monotonic() - t2
    if not a.parts:
        shutil.rmtree(parts_dir, ignore_errors=True)
    per_shard = [s for _, _, s, _ in sorted(results)]
    timing = {
        "shards": a.shards,
        "ray_init_s": round(t_init, 3),
        "shards_wall_s": round(t_shards, 3),
        "merge_s": round(t_merge, 3),
        "total_s": round(time.monotonic() - t0, 3),
        "per_shard_s": [round(s, 3) for s in per_shard],
    }
    print(f"ray_study: {a.shards} shards in {t_shards:.2f} s (Ray start {t_init:.2f} s, slowest shard {max(per_shard):.2f} s), merge {t_merge:.2f} s", file=sys.stderr)
    if a.timings:
        with open(a.timings + ".tmp", "w") as f:
            json.dump(timing, f, indent=2)
        os.replace(a.timings + ".tmp", a.timings)
    return code


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
