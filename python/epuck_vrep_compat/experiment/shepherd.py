"""The shepherd of one run: ``python3 -m epuck_vrep_compat.experiment.shepherd RUN_DIR``.

One small process per run between the Dask worker and roslaunch. It becomes a child
subreaper, so whatever roslaunch starts (the master, the nodes: roslaunch gives each its own
session) stays its descendant even when roslaunch dies; it starts ``roslaunch`` on the run's
launch file and waits for it to end (the probe ends it when the simulated time is up), for the
wall-time limit, for SIGTERM/SIGINT, or for its parent (the worker) to die. Then it ends every
process of the run (SIGINT to roslaunch first, so bags close; then SIGTERM and SIGKILL to what
is left of its descendants and of the run's marked processes), reaps them, and writes
``shepherd.json``: roslaunch's exit status, whether the time ran out, what had to be killed,
the CPU time the run's processes used.
"""
import ctypes
import json
import os
import signal
import subprocess
import sys
import time

from epuck_vrep_compat.experiment import isolation

PR_SET_CHILD_SUBREAPER = 36
SIGINT_GRACE_S = 20.0     # roslaunch's time to end its nodes on SIGINT before SIGTERM [s]


class Stop(Exception):
    """SIGTERM or SIGINT: end the run now."""


def _descendants():
    """Pids whose parent chain reaches this process (all of them, as a subreaper)."""
    parents = {}
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            try:
                with open(f"/proc/{entry}/stat", "rb") as f:
                    parents[int(entry)] = int(f.read().rsplit(b")", 1)[1].split()[1])
            except (OSError, IndexError, ValueError):
                continue
    me, out = os.getpid(), []
    for pid in parents:
        p, seen = pid, 0
        while p in parents and p > 1 and seen < 64:
            p, seen = parents[p], seen + 1
            if p == me:
                out.append(pid)
                break
    return out


def _reap():
    while True:
        try:
            pid, _ = os.waitpid(-1, os.WNOHANG)
        except ChildProcessError:
            return
        if pid == 0:
            return


def end_everything(launch, run_marker, sigint_grace_s=SIGINT_GRACE_S):
    """SIGINT to roslaunch and every process of the run at once (each node shuts down as on
    Ctrl-C, bags close; all together, not one after the other as roslaunch would), then
    SIGTERM and SIGKILL to whatever is left after ``sigint_grace_s``; roslaunch is reaped as
    ``launch`` (its status stays in ``launch.returncode``)."""
    if launch.poll() is None:
        for pid in [launch.pid] + _descendants():
            try:
                os.kill(pid, signal.SIGINT)
            except OSError:
                pass
        try:
            launch.wait(sigint_grace_s)
        except subprocess.TimeoutExpired:
            pass
    left = sorted(set(_descendants()) | set(isolation.processes_marked(
        isolation.RUN_MARKER, run_marker)))
    killed = isolation.terminate(left, grace_s=5.0)
    # roslaunch's own status first (SIGTERM's or SIGKILL's when it outlived SIGINT, e.g. on
    # a loaded machine): the sweep below reaps any child, and one it reaped would leave the
    # run without roslaunch's exit status
    try:
        launch.wait(5.0)
    except subprocess.TimeoutExpired:
        pass
    deadline = time.monotonic() + 5.0
    while time.monotonic() < deadline:
        _reap()
        if not _descendants():
            break
        time.sleep(0.05)
    return left, killed


def main(argv=None):
    run_dir = (argv or sys.argv[1:])[0]
    with open(os.path.join(run_dir, "shepherd_in.json")) as f:
        job = json.load(f)
    libc = ctypes.CDLL(None, use_errno=True)
    libc.prctl(PR_SET_CHILD_SUBREAPER, 1, 0, 0, 0)
    # the worker that started it, as it said (not getppid() now: a worker killed while
    # this process was still starting would leave it a parent already changed)
    parent = job.get("parent") or os.getppid()

    def stop(_sig, _frame):
        raise Stop()
    signal.signal(signal.SIGTERM, stop)
    signal.signal(signal.SIGINT, stop)
    out = {"exit_code": None, "timed_out": False, "stopped": False, "orphaned": False,
           "times": {"launch": time.time()}}
    with open(os.path.join(run_dir, "launch.log"), "wb") as log:
        launch = subprocess.Popen(job["command"], stdout=log, stderr=subprocess.STDOUT,
                                  env=job["env"], cwd=run_dir)
    deadline = time.monotonic() + job["timeout_s"]
    try:
        while launch.poll() is None:
            if os.path.exists(job.get("done_file", "")):
                out["done"] = True           # the probe has written the run: end it now
                break
            if time.monotonic() > deadline:
                out["timed_out"] = True
                break
            if os.getppid() != parent:
                out["orphaned"] = True
                break
            time.sleep(0.1)
    except Stop:
        out["stopped"] = True
    signal.signal(signal.SIGTERM, signal.SIG_IGN)
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    out["times"]["launch_end"] = time.time()
    left, killed = end_everything(launch, job["env"][isolation.RUN_MARKER])
    out["times"]["clean"] = time.time()
    out["exit_code"] = launch.returncode
    # every process of the run was reaped by roslaunch or by this subreaper, so their CPU time
    # (user + system, all threads) is in this process's children's: the run's cost, whatever
    # else the machine was doing
    spent = os.times()
    out["cpu_s"] = round(spent.children_user + spent.children_system, 3)
    out["left_at_end"], out["killed"] = len(left), len(killed)
    with open(os.path.join(run_dir, "shepherd.json"), "w") as f:
        json.dump(out, f)
    return 0


if __name__ == "__main__":
    sys.exit(main())
