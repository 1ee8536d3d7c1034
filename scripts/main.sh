#!/usr/bin/env bash
# The main job on the built-in default: builds Verity and runs the default study
# (scenes/studies/area-lights.toml: area-light shading, representative point vs N×N
# quadrature) with `verity report`, writing out/area-lights/index.html, metrics.json,
# metrics.csv, the EXRs and charts. Extra arguments go to `verity report` (e.g. --quick).
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/setup.sh
cargo build --release --locked -p compare --bin verity
./target/release/verity report "$@"
