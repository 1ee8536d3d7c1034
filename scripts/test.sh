#!/usr/bin/env bash
# Runs every Verity test, after installing what they need (scripts/setup.sh).
# This is the README's test command and exactly what CI (.ci/run) runs.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/setup.sh
cargo fmt --all -- --check
cargo clippy --workspace --all-targets --locked -- -D warnings
# lavapipe compiles a pipeline's shaders with LLVM when a frame first draws with it, and from
# a cold Mesa shader cache (a fresh machine, as in CI) those compiles are most of the realtime
# tests' time. GALLIVM_PERF=nopt (Mesa's gallivm) skips LLVM's optimisation passes: the same
# images (every quick metric of the texture-filtering, energy-compensation and envmap-roughness
# studies identical), shaders that run slower (no test times anything), and
# realtime/tests/texture took 95 s instead of 168. A value already set is kept.
export GALLIVM_PERF="${GALLIVM_PERF-nopt}"
cargo test --workspace --locked
