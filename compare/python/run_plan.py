"""Runs a study's job graph (`verity report STUDY --plan PLAN`) on a Dask cluster.

Every job of the plan but the report becomes a Dask task that runs `verity run-job PLAN JOB` on
a worker, after the tasks of the jobs it depends on (a ground truth after its parts, with
`--parts`); ground-truth and raster jobs run side by side. When all are done, the report job
(`verity report --from PLAN`) runs here, on the machine that drives the cluster: it only
measures, from the cache and the recorded rasters. Workers must see the plan, the study's
files, the same Verity build and the plan's cache and report folders (a shared file system
on a real cluster), and raster jobs need a GPU adapter or lavapipe on the worker. Verity
writes every output atomically, with its checksum after it, so a worker that dies mid-job
leaves no half-written file: the task is simply run again elsewhere (Dask reschedules the
tasks of a lost worker; `--retries` more times if a job itself fails).

Why Dask: `distributed` runs the same code on a laptop's LocalCluster and, through
`dask-jobqueue`, on Slurm, PBS or SGE, with task retries and worker-loss recovery built in, and
it is a pure-Python install into the project's venv (Ray would bring its own cluster
daemons, a larger footprint for the same job graph).

    run_plan.py PLAN [--verity PATH] (--local N | --jobqueue slurm|pbs|sge | --scheduler ADDRESS)

`--local N` starts a LocalCluster of N worker processes on 127.0.0.1. `--jobqueue slurm`
(or pbs, sge) submits `--jobs J` batch jobs through dask-jobqueue, each one Dask worker with
`--cores C` and `--memory M` booked (`--walltime`, `--queue`, `--account`, `--interface`,
`--job-directive` as the queue needs; the scheduler runs here, on `--host` if given).
`--scheduler tcp://HOST:8786` connects to a running scheduler whose workers were started
by hand (`dask worker ADDRESS --nthreads 1`). A Verity job uses every core of its machine,
so a worker runs one job at a time: the tasks ask for the worker resource `verity=1`, which
the workers this driver starts have once. Exit status: that of `verity report --from`
(0: every bound held, 1: a bound failed, 2 or 3: an error), or 1 when a job failed after its
retries (its dependants are not run).

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

# A worker runs one Verity job at a time (each uses every core it finds).
RESOURCES = {"verity": 1}


def run_job(verity, plan, job, *_done):
    """`verity run-job PLAN JOB` on a worker, after the jobs whose results are `_done`; its
    output line, or an exception with stderr."""
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
    where.add_argument("--jobqueue", choices=["slurm", "pbs", "sge"],
                       help="workers as batch jobs of this queue system (dask-jobqueue)")
    where.add_argument("--scheduler", metavar="ADDRESS", help="a running Dask scheduler")
    p.add_argument("--retries", type=int, default=2, help="reruns of a failing job (default 2)")
    q = p.add_argument_group("--jobqueue")
    q.add_argument("--jobs", type=int, default=4, help="batch jobs, one worker each (default 4)")
    q.add_argument("--cores", type=int, default=8, help="cores booked per job (default 8)")
    q.add_argument("--memory", default="16GB", help="memory booked per job (default 16GB)")
    q.add_argument("--walltime", default="02:00:00", help="wall time per job (default 02:00:00)")
    q.add_argument("--queue", help="queue or partition")
    q.add_argument("--account", help="account or project to charge")
    q.add_argument("--interface", help="network interface of scheduler and workers (e.g. ib0)")
    q.add_argument("--host", help="address the scheduler listens on (default: the interface's)")
    q.add_argument("--job-directive", action="append", default=[], metavar="LINE",
                   help="an extra directive for the job script, e.g. '--gres=gpu:1' (repeatable)")
    return p.parse_args()


def jobqueue_cluster(a):
    """A dask-jobqueue cluster of `a.jobs` batch jobs, each one single-job worker."""
    try:
        import dask_jobqueue
    except ImportError as e:
        print(f"run_plan.py: {e}; run ./scripts/setup.sh to install the venv", file=sys.stderr)
        sys.exit(3)
    kind = {"slurm": dask_jobqueue.SLURMCluster, "pbs": dask_jobqueue.PBSCluster,
            "sge": dask_jobqueue.SGECluster}[a.jobqueue]
    options = dict(cores=a.cores, processes=1, memory=a.memory, walltime=a.walltime,
                   queue=a.queue, account=a.account, interface=a.interface,
                   job_extra_directives=a.job_directive,
                   worker_extra_args=["--resources", "verity=1"])
    if a.jobqueue == "sge":
        options.pop("account")
        options["project"] = a.account
    if a.host:
        options["scheduler_options"] = {"host": a.host, "dashboard_address": None}
    cluster = kind(**options)
    cluster.scale(jobs=a.jobs)
    return cluster


def main():
    a = parse_args()
    plan = os.path.abspath(a.plan)
    with open(plan) as f:
        jobs = [j for j in json.load(f)["jobs"] if j["kind"] != "report"]
    verity = os.path.abspath(a.verity) if os.sep in a.verity else a.verity
    if a.local is not None:
        cluster = LocalCluster(n_workers=a.local, threads_per_worker=1, processes=True,
                               host="127.0.0.1", dashboard_address=None, resources=RESOURCES)
    elif a.jobqueue is not None:
        cluster = jobqueue_cluster(a)
    else:
        cluster = None
    client = Client(cluster if cluster is not None else a.scheduler)
    try:
        resources = RESOURCES if cluster is not None else None
        futures = {}
        for j in jobs:  # the plan lists every job after those it depends on
            after = [futures[d] for d in j["depends_on"]]
            futures[j["id"]] = client.submit(run_job, verity, plan, j["id"], *after,
                                             key=f"verity-{j['id']}", pure=False,
                                             retries=a.retries, resources=resources)
        failed = 0
        for future in as_completed(list(futures.values())):
            try:
                print(future.result(), flush=True)
            except Exception as e:  # a job that failed after its retries, or a dependant of one
                print(f"run_plan.py: {future.key}: {e}", file=sys.stderr)
                failed += 1
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
    if failed:
        print(f"run_plan.py: {failed} of {len(jobs)} jobs failed; the report was not made",
              file=sys.stderr)
        return 1
    return subprocess.run([verity, "report", "--from", plan, "-q"]).returncode


if __name__ == "__main__":
    sys.exit(main())
