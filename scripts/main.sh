#!/usr/bin/env bash
# The main job on the built-in default: builds Verity and renders the default scene with the
# oracle, writing out/cornell-box.exr (+ .png preview). Extra arguments go to `verity render`.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/setup.sh
cargo build --release --locked -p compare --bin verity
./target/release/verity render scenes/cornell-box.toml "$@"
