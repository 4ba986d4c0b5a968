#!/usr/bin/env bash
# A grove study as a Slurm job array: array task K re-simulates shard K of N and writes its
# partial result; one job that waits for the array merges them into the reports.
#
#   submit (on the login node):
#     GROVE=$HOME/bin/grove REPLAYS=$PWD/replays/study PARTS=$PWD/parts OUT=$PWD/reports \
#       scripts/slurm_study.sh submit 100
#   what each array task runs (Slurm sets SLURM_ARRAY_TASK_ID; SHARDS comes from submit):
#     scripts/slurm_study.sh shard
#   what the merge job runs:
#     scripts/slurm_study.sh merge
#
# Settings, from the environment (submit passes them on with --export):
#   GROVE    the grove binary, at the same path on every node (default: grove on PATH)
#   REPLAYS  the folder of recordings (shared file system); or, with SYNTH_PARTICIPANTS, unused
#   SYNTH_PARTICIPANTS, SYNTH_SEED, SYNTH_SET
#            each task synthesises its shard of the participants into node-local $TMPDIR instead
#            (SYNTH_SET: a NAME=VALUE for re-simulated participants, compared with the baseline)
#   SET      a --set argument for grove study (a what-if or a sweep on the replayed hands)
#   PARTS    where the partial results go (shared file system)
#   OUT      where the merged reports go
#   SHARDS   the number of shards (set by submit to the array's size)
# Extra sbatch options (account, partition, time) go in SBATCH_OPTS, e.g. "--partition=cpu -A lab".
# docs/scale.md walks through a run.
set -euo pipefail

GROVE="${GROVE:-grove}"
PARTS="${PARTS:?set PARTS to the folder of the partial results}"
cmd="${1:-}"

case "$cmd" in
submit)
  n="${2:?usage: slurm_study.sh submit N}"
  case "$n" in '' | *[!0-9]* | 0) echo "slurm_study.sh: N must be a positive number, not '$n'" >&2; exit 2 ;; esac
  mkdir -p "$PARTS"
  here="$(cd "$(dirname "$0")" && pwd)/$(basename "$0")"
  # shellcheck disable=SC2086
  array=$(sbatch --parsable ${SBATCH_OPTS:-} --job-name=grove-shard --array="1-$n" --cpus-per-task=1 \
    --export=ALL,SHARDS="$n" --output="$PARTS/slurm-%A_%a.log" "$here" shard)
  # shellcheck disable=SC2086
  sbatch --parsable ${SBATCH_OPTS:-} --job-name=grove-merge --dependency="afterok:${array%%;*}" \
    --export=ALL,SHARDS="$n" --output="$PARTS/slurm-merge-%j.log" "$here" merge
  echo "submitted the array ${array%%;*} ($n shards) and its merge; partial results in $PARTS" >&2
  ;;
shard)
  k="${SLURM_ARRAY_TASK_ID:?shard runs as a Slurm array task (SLURM_ARRAY_TASK_ID)}"
  n="${SHARDS:-${SLURM_ARRAY_TASK_COUNT:?set SHARDS}}"
  part="$PARTS/part-$(printf %05d "$k")-of-$n"
  # One re-simulation at a time per CPU Slurm gave the task.
  export RAYON_NUM_THREADS="${SLURM_CPUS_PER_TASK:-1}"
  set_args=()
  if [ -n "${SET:-}" ]; then set_args=(--set "$SET"); fi
  if [ -n "${SYNTH_PARTICIPANTS:-}" ]; then
    work="$(mktemp -d "${TMPDIR:-/tmp}/grove-shard-$k-XXXXXX")"
    trap 'rm -rf "$work"' EXIT
    synth=("$GROVE" synth --participants "$SYNTH_PARTICIPANTS" --seed "${SYNTH_SEED:-2019}" --shard "$k/$n")
    "${synth[@]}" --out "$work/baseline" >/dev/null
    if [ -n "${SYNTH_SET:-}" ]; then
      "${synth[@]}" --out "$work/what-if" --set "$SYNTH_SET" >/dev/null
      study=(--replays "$work/what-if" --baseline "$work/baseline")
    else
      study=(--replays "$work/baseline")
    fi
  else
    study=(--replays "${REPLAYS:?set REPLAYS to the folder of recordings}")
  fi
  # Exit 1 means some recording failed or diverged: the partial result is written all the same.
  "$GROVE" study "${study[@]}" "${set_args[@]}" --shard "$k/$n" --out "$part" --force || [ $? -eq 1 ]
  ;;
merge)
  n="${SHARDS:?set SHARDS}"
  parts=()
  for k in $(seq 1 "$n"); do parts+=("$PARTS/part-$(printf %05d "$k")-of-$n"); done
  exec "$GROVE" study merge "${parts[@]}" --out "${OUT:?set OUT to the folder of the reports}" ${FORCE:+--force}
  ;;
*)
  echo "usage: slurm_study.sh submit N | shard | merge (see the comments at its top)" >&2
  exit 2
  ;;
esac
