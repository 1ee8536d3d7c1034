#!/usr/bin/env bash
# Every study in full mode (the size users run them), one process each, and their full-mode
# records: builds Verity, runs `verity report --all --record`, which writes
# out/all-studies/<study>/ (each report), out/all-studies/summary.md and summary.json (study,
# mode, bounds held, wall time, peak memory) and, at the end of each study file, the record
# of this run (date, fingerprint of the study and its scene, bounds, figures) that
# tests/tests/studies.rs checks. Takes hours on 2 cores; ground truths are cached in
# out/cache, so a second run re-renders only what changed; `--stale` runs only the studies
# whose record is missing, out of date, made with another oracle or failed (resumes a run
# that was cut off). Extra
# arguments go to `verity report --all` (e.g. --stale, --out DIR, --cache DIR); the memory
# limit goes through VERITY_MEMORY_LIMIT. Exit status: that of `verity report --all` (0: every bound held).
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/setup.sh
cargo build --release --locked -p compare --bin verity
exec ./target/release/verity report --all --record "$@"
