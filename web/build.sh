#!/usr/bin/env bash
# Builds grove's simulation as a WebAssembly module (web/sim, release, no debug info) into
# target/wasm/grove_sim.wasm, in a target folder of its own so that it never invalidates the
# native build. From a fresh clone: `bash web/build.sh` (it adds the wasm32 target with rustup
# when it is missing). docs/wasm.md; web/sim/README.md.
set -euo pipefail
cd "$(dirname "$0")/.."
if ! rustup target list --installed 2>/dev/null | grep -qx wasm32-unknown-unknown; then
  rustup target add wasm32-unknown-unknown
fi
out="${CARGO_TARGET_DIR:-target}/wasm"
# No SIMD (wasm's NaN bit patterns are not deterministic): the target's default features only.
case "${RUSTFLAGS:-} ${CARGO_ENCODED_RUSTFLAGS:-}" in
  *simd128*|*relaxed-simd*) echo "web/build.sh: RUSTFLAGS turn on wasm SIMD, which the module must not use (docs/wasm.md)" >&2; exit 2 ;;
esac
CARGO_PROFILE_RELEASE_DEBUG=0 CARGO_PROFILE_RELEASE_STRIP=true \
  cargo build --locked --release -q --target wasm32-unknown-unknown -p grove-web-sim --target-dir "$out"
cp "$out/wasm32-unknown-unknown/release/grove_web_sim.wasm" "$out/grove_sim.wasm"
echo "$out/grove_sim.wasm: $(wc -c < "$out/grove_sim.wasm") bytes, $(gzip -9 -c "$out/grove_sim.wasm" | wc -c) gzipped"
