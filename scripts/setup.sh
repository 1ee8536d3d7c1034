#!/usr/bin/env bash
# Installs what Verity's builds and tests need on a fresh Debian machine, skipping what is
# already there. Idempotent; safe to run every time. Needs root (or sudo) for apt-get.
set -euo pipefail
cd "$(dirname "$0")/.."

say() { printf 'setup: %s\n' "$*"; }

if ! command -v cargo >/dev/null 2>&1; then
  say "cargo not found: install the Rust toolchain (rustup, Rust >= 1.85) first." >&2
  exit 1
fi

# Debian packages: name -> why.
need_apt=()
want() { dpkg -s "$1" >/dev/null 2>&1 || need_apt+=("$1"); }
want pkg-config        # -sys crates
want python3-venv      # the pinned Python tools (Mitsuba, flip-evaluator) live in .venv
want libllvm19         # Mitsuba's llvm_ad_rgb variant JIT-compiles with LLVM (DRJIT_LIBLLVM_PATH)
want libvulkan1        # the Vulkan loader wgpu opens (realtime renderer)
want mesa-vulkan-drivers  # lavapipe: a Vulkan CPU driver, so the realtime tests run without a GPU
want chromium          # headless browser for the three.js client (examples/threejs, WebGL2 on SwiftShader)
# Node and npm for examples/threejs; Debian's packages only where none is installed (a
# NodeSource nodejs ships its own npm and conflicts with Debian's npm package).
command -v node >/dev/null 2>&1 || want nodejs
command -v npm >/dev/null 2>&1 || want npm

if [ ${#need_apt[@]} -gt 0 ]; then
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  say "apt-get install ${need_apt[*]}"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${need_apt[@]}" >/dev/null
fi
# The Python venv for the Mitsuba 3 cross-check (compare/python/requirements.txt, pinned).
# Nothing is exported: verity finds .venv/bin/python itself (or $VERITY_PYTHON). The stamp
# records the requirements last installed, so a run with nothing to do is instant. If the
# install fails, setup says so and goes on: the other tests still run, and the cross-check
# tests fail with the reason (they never skip).
REQ=compare/python/requirements.txt
STAMP=.venv/.verity-requirements
install_venv() {
  [ -x .venv/bin/python ] || { say "creating .venv"; python3 -m venv .venv; } || return 1
  say "pip install -r $REQ (into .venv)"
  .venv/bin/python -m pip install --quiet --disable-pip-version-check -r "$REQ" || return 1
  .venv/bin/python -c "import mitsuba, numpy; assert mitsuba.__version__ == '3.9.1', mitsuba.__version__" \
    || return 1
  cp "$REQ" "$STAMP"
}
if [ ! -x .venv/bin/python ] || ! cmp -s "$REQ" "$STAMP"; then
  install_venv || say "WARNING: could not install $REQ into .venv; the Mitsuba cross-check tests will fail" >&2
fi
# The large-mesh bench scene's glTF (scenes/bench/rock.glb, 31 MB, generated, not committed):
# written once, and again when its generator changes. Its cross-check test fails (never
# skips) without it.
ROCK=scenes/bench/rock.glb
if [ ! -f "$ROCK" ] || [ scenes/bench/make_rock.py -nt "$ROCK" ]; then
  say "writing $ROCK (scenes/bench/make_rock.py)"
  .venv/bin/python scenes/bench/make_rock.py \
    || say "WARNING: could not write $ROCK; its cross-check test will fail" >&2
fi
# The three.js client's npm packages (examples/threejs/package-lock.json, pinned). The stamp
# (inside node_modules, which npm ci recreates) records the lockfile last installed. Unlike
# the venv, a failure stops setup: the three.js test cannot run without these, and it fails
# (never skips) when they are missing.
TJ=examples/threejs
TJ_STAMP=$TJ/node_modules/.verity-package-lock.json
for tool in chromium node npm; do
  command -v "$tool" >/dev/null 2>&1 || {
    say "ERROR: $tool is not installed (apt-get install chromium nodejs npm); the three.js test will fail" >&2
    exit 1
  }
done
if [ ! -d "$TJ/node_modules" ] || ! cmp -s "$TJ/package-lock.json" "$TJ_STAMP"; then
  say "npm ci (in $TJ)"
  (cd "$TJ" && npm ci --no-audit --no-fund --loglevel=error) || {
    say "ERROR: npm ci failed in $TJ; the three.js test will fail" >&2
    exit 1
  }
  cp "$TJ/package-lock.json" "$TJ_STAMP"
fi
say "ok"
