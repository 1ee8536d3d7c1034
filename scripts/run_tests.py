#!/usr/bin/env python3
"""Runs every test binary of the workspace, several at a time, longest first.

`cargo test --workspace` runs its test binaries one after another. Most of Verity's spend
their time in one thread (lavapipe compiling a pipeline, one oracle tile row at a time for a
64² image), so a 2-core machine sat at a load of 1.0 through CI. This script builds the tests
once (`cargo test --no-run`), then runs the binaries JOBS at a time, the slowest first (by the
durations the last run measured, else by scripts/test-durations.txt), each in its package's
folder as cargo would, and the doc tests beside them. Each binary's output goes to
target/test-logs/<binary>.log and is printed whole if it fails; a line per binary says how it
ended and how long it took. The exit status is 1 if any binary failed, else 0.

Usage: scripts/run_tests.py [--jobs N]   (default: VERITY_TEST_JOBS, else the number of
CPUs, at most 4: each study child peaks near 2 GB and the studies binary runs two)
"""

import argparse
import json
import os
import subprocess
import sys
import threading
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SEED_DURATIONS = ROOT / "scripts" / "test-durations.txt"
LOGS = ROOT / "target" / "test-logs"
MEASURED_DURATIONS = LOGS / "durations.txt"


def read_durations(path):
    """`seconds name` per line (the format written after each run); {} if the file is missing."""
    durations = {}
    if path.exists():
        for line in path.read_text().splitlines():
            parts = line.split(maxsplit=1)
            if len(parts) == 2 and not line.startswith("#"):
                durations[parts[1]] = float(parts[0])
    return durations


def test_binaries():
    """Builds every test target (--locked) and returns (name, executable, package folder)."""
    build = subprocess.run(
        ["cargo", "test", "--workspace", "--locked", "--no-run",
         "--message-format=json-render-diagnostics"],
        cwd=ROOT, stdout=subprocess.PIPE, text=True)
    binaries = []
    for line in build.stdout.splitlines():
        message = json.loads(line)  # cargo renders compiler messages to stderr itself
        if message.get("reason") != "compiler-artifact" or not message.get("executable"):
            continue
        if not message["profile"]["test"]:
            continue
        target = message["target"]
        package = Path(message["manifest_path"]).parent
        kind = "unittests" if target["kind"] != ["test"] else "tests"
        name = f"{package.name}/{kind}/{target['name']}"
        binaries.append((name, message["executable"], package))
    if build.returncode != 0:
        sys.exit(f"run_tests: the tests do not build (cargo exited {build.returncode})")
    return binaries


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    default_jobs = int(os.environ.get("VERITY_TEST_JOBS", min(os.cpu_count() or 1, 4)))
    parser.add_argument("--jobs", type=int, default=default_jobs)
    jobs = max(1, parser.parse_args().jobs)

    binaries = test_binaries()
    LOGS.mkdir(parents=True, exist_ok=True)
    expected = read_durations(SEED_DURATIONS) | read_durations(MEASURED_DURATIONS)
    queue = [(name, [exe], package) for name, exe, package in binaries]
    queue.append(("doc-tests", ["cargo", "test", "--workspace", "--locked", "--doc"], ROOT))
    # Longest first; a binary never measured (a new one) goes first too, as it may be long.
    queue.sort(key=lambda job: -expected.get(job[0], float("inf")))

    lock = threading.Lock()
    results = {}
    start = time.monotonic()

    def worker():
        while True:
            with lock:
                if not queue:
                    return
                name, command, cwd = queue.pop(0)
            log = LOGS / (name.replace("/", "--") + ".log")
            env = dict(os.environ, CARGO_MANIFEST_DIR=str(cwd))
            t0 = time.monotonic()
            with open(log, "w") as out:
                status = subprocess.run(command, cwd=cwd, env=env, stdout=out,
                                        stderr=subprocess.STDOUT).returncode
            seconds = time.monotonic() - t0
            text = log.read_text(errors="replace")
            summary = [l for l in text.splitlines() if l.startswith("test result:")]
            with lock:
                results[name] = (status, seconds)
                verdict = "ok  " if status == 0 else "FAIL"
                print(f"{verdict} {seconds:7.1f} s  {name}  "
                      f"{summary[-1] if summary else ''}", flush=True)
                if status != 0:
                    print(f"---- {name} (exit {status}), {log} ----\n{text}\n---- end of {name} ----",
                          flush=True)

    print(f"run_tests: {len(queue)} test binaries, {jobs} at a time", flush=True)
    threads = [threading.Thread(target=worker) for _ in range(jobs)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()

    MEASURED_DURATIONS.write_text(
        "".join(f"{s:.1f} {n}\n" for n, (_, s) in sorted(results.items(), key=lambda r: -r[1][1])))
    failed = sorted(n for n, (status, _) in results.items() if status != 0)
    print(f"run_tests: {len(results) - len(failed)} of {len(results)} binaries passed in "
          f"{time.monotonic() - start:.0f} s ({jobs} at a time); durations in {MEASURED_DURATIONS}")
    if failed:
        print("run_tests: failed: " + ", ".join(failed))
        sys.exit(1)


if __name__ == "__main__":
    main()
