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

if [ ${#need_apt[@]} -gt 0 ]; then
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  say "apt-get install ${need_apt[*]}"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${need_apt[@]}" >/dev/null
fi
say "ok"
