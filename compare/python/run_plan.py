"""Runs a study's job graph (`verity report STUDY --plan PLAN`) on a Dask cluster.

Every ground-truth job becomes a Dask task that runs `verity run-job PLAN JOB` on a worker;
when all are done, the report job (`verity report --from PLAN`) runs here, on the machine that
drives the cluster (it needs a GPU adapter or lavapipe). Workers must see the plan, the study's
files, the same Verity build and the plan's cache folder (a shared file system on a real
cluster). Verity writes each cache entry atomically, with its checksum after it, so a worker
that dies mid-job leaves no half-written ground truth: the task is simply run again elsewhere
(Dask reschedules the tasks of a lost worker; `--retries` more times if a job itself fails).

Why Dask: `distributed` runs the same code on a laptop's LocalCluster and, through
`dask-jobqueue`, on Slurm, PBS or SGE, with task retries and worker-loss recovery built in, and
it is a pure-Python install into the project's venv (Ray would bring its own cluster
daemons, a larger footprint for the same job graph).

    run_plan.py PLAN [--verity PATH] (--local N | --scheduler ADDRESS) [--retries R]

`--local N` starts a LocalCluster of N single-threaded worker processes on 127.0.0.1; 
`--scheduler tcp://HOST:8786` connects to a running scheduler (e.g. one started by
dask-jobqueue's SLURMCluster, or `dask scheduler` and `dask worker` by hand). Exit status:
that of `verity report --from` (0: every bound held, 1: a bound failed, 2 or 3: an error),
or 1 when a ground-truth job failed after its retries.

Fault injection for the tests only: with VERITY_DASK_DIE_ONCE=FILE set, the first task to
start creates FILE and ends its worker process abruptly (as a machine lost mid-job would).
"""

import argparse
import json
import os
import subprocess
import sys

try:
    from distributed import Client, LocalCluster, as_completed
except ImportError as e:  # the Rust test turns this exit code into "run ./scripts/setup.sh"
    print(f"run_plan.py: {e}; run ./scripts/setup.sh to install the venv", file=sys.stderr)
    sys.exit(3)


def run_job(verity, plan, job):
    """`verity run-job PLAN JOB` on a worker; its output line, or an exception with stderr."""
    marker = os.environ.get("VERITY_DASK_DIE_ONCE")
    if marker:
        try:
            with open(marker, "x"):
                pass
            os._exit(1)  # the worker process dies mid-job
        except FileExistsError:
            pass
    done = subprocess.run([verity, "run-job", plan, job, "-q"], capture_output=True, text=True)
    if done.returncode != 0:
        raise RuntimeError(f"verity run-job {job}: exit {done.returncode}: {done.stderr.strip()}")
    return done.stdout.strip()


def parse_args():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("plan")
    p.add_argument("--verity", default="verity", help="the verity binary (default: on PATH)")
    where = p.add_mutually_exclusive_group(required=True)
    where.add_argument("--local", type=int, metavar="N", help="a LocalCluster of N worker processes")
    where.add_argument("--scheduler", metavar="ADDRESS", help="a running Dask scheduler")
    p.add_argument("--retries", type=int, default=2, help="reruns of a failing job (default 2)")
    return p.parse_args()


def main():
    a = parse_args()
    plan = os.path.abspath(a.plan)
    with open(plan) as f:
        jobs = [j["id"] for j in json.load(f)["jobs"] if j["kind"] == "ground_truth"]
    verity = os.path.abspath(a.verity) if os.sep in a.verity else a.verity
    if a.local is not None:
        cluster = LocalCluster(n_workers=a.local, threads_per_worker=1, processes=True,
                               host="127.0.0.1", dashboard_address=None)
        client = Client(cluster)
    else:
        cluster, client = None, Client(a.scheduler)
    try:
        futures = [client.submit(run_job, verity, plan, job, key=f"verity-{job}", pure=False,
                                 retries=a.retries) for job in jobs]
        failed = 0
        for future in as_completed(futures):
            try:
                print(future.result(), flush=True)
            except Exception as e:  # a job that failed after its retries
                print(f"run_plan.py: {e}", file=sys.stderr)
                failed += 1
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
    if failed:
        print(f"run_plan.py: {failed} of {len(jobs)} ground-truth jobs failed; the report was not made",
              file=sys.stderr)
        return 1
    return subprocess.run([verity, "report", "--from", plan, "-q"]).returncode


if __name__ == "__main__":
    sys.exit(main())
