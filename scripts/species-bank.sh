#!/usr/bin/env bash
# Writes the shipped species bank, assets/banks/species (docs/species.md, "The shipped species
# bank"): every preset in assets/species at seed 1, its level of detail 1 (about 25 % of the
# triangles) as the mesh model NAME-lod1 and its level of detail 2 (about 5 %) as the billboard
# model NAME-lod2, through `grove trees generate --add`; NAME-lod1 names NAME-lod2 as its far
# model, which the renderer draws in its place where the tree is small on screen. The same grove writes the same bytes; tests/integration/species_bank.rs
# checks that the committed bank is what this script writes.
#
#   scripts/species-bank.sh [GROVE_BINARY] [BANK_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
grove="${1:-target/release/grove}"
bank="${2:-assets/banks/species}"
if [ -e "$bank" ]; then
  echo "scripts/species-bank.sh: $bank exists; remove it first to write it anew" >&2
  exit 2
fi
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
for species in oak birch beech scots_pine norway_spruce shrub; do
  "$grove" trees generate --species "$species" --seed 1 --out "$work/$species-2" --add --bank "$bank" --lod 2 --kind billboard
  "$grove" trees generate --species "$species" --seed 1 --out "$work/$species-1" --add --bank "$bank" --lod 1 --kind mesh --far "$species-lod2"
done
