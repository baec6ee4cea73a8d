#!/usr/bin/env bash
# Builds the settings page's protocol module (the `wasm` crate) into web/imu_protocol.wasm.
# `--check`: build it and fail if it differs from the committed copy (CI does this).
# Paths are remapped so that the bytes do not depend on where the checkout or the cargo
# registry lives.
set -euo pipefail
cd "$(dirname "$0")/.."
rustup target add wasm32-unknown-unknown >/dev/null 2>&1 || true
RUSTFLAGS="--remap-path-prefix=$PWD=/imu-mouse --remap-path-prefix=${CARGO_HOME:-$HOME/.cargo}=/cargo" \
  cargo build -q --profile wasm -p wasm --target wasm32-unknown-unknown
built=target/wasm32-unknown-unknown/wasm/imu_wasm.wasm
if [ "${1:-}" = "--check" ]; then
  if ! cmp -s "$built" web/imu_protocol.wasm; then
    echo "web/imu_protocol.wasm is not what the wasm crate builds: run bash web/build-wasm.sh and commit it" >&2
    exit 1
  fi
  echo "web/imu_protocol.wasm matches the wasm crate ($(stat -c %s "$built") bytes)"
else
  cp "$built" web/imu_protocol.wasm
  echo "web/imu_protocol.wasm: $(stat -c %s "$built") bytes"
fi
