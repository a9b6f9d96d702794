"""Helpers of the experiment tier: the CLI as a user runs it, its results folder, and this
user's processes read from /proc (pid, start time, parent, state, command line, environment).

Every process a test starts inherits ``EVC_TEST_TOKEN`` (a value new for each test, set by
conftest's ``no_process_left``); roslaunch hands its environment on to every node and the
master, Dask to its workers. That token, not a name, says which processes are the test's: the
machine is shared, and other engineers' experiments and masters (same user) must be neither
blamed nor touched.
"""
import csv
import json
import os
import signal
import subprocess
import time

import pyarrow.parquet as pq

from repo import fixtures_of

FIXTURES = fixtures_of("experiment")
TOKEN = "EVC_TEST_TOKEN"
PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"
CLI_TIMEOUT_S = 900             # only against hanging forever; never an assertion of speed


def fixture(name):
    return os.path.join(FIXTURES, name)


# --- processes ---------------------------------------------------------------------------------
class Proc:
    """One process as /proc showed it: identity (pid, start time in clock ticks since boot),
    parent, state; command line and environment read on demand."""

    def __init__(self, pid, ppid, state, start):
        self.pid, self.ppid, self.state, self.start = pid, ppid, state, start

    @property
    def ident(self):
        return (self.pid, self.start)

    @property
    def alive(self):
        return self.state not in ("Z", "X")          # a zombie has ended

    def cmdline(self):
        try:
            with open(f"/proc/{self.pid}/cmdline", "rb") as f:
                return f.read().replace(b"\0", b" ").decode(errors="replace").strip()
        except OSError:
            return "?"

    def environ(self):
        """{name: value} of its environment (as it was when it started), {} once gone."""
        try:
            with open(f"/proc/{self.pid}/environ", "rb") as f:
                items = f.read().split(b"\0")
        except OSError:
            return {}
        out = {}
        for item in items:
            name, sep, value = item.partition(b"=")
            if sep:
                out[name.decode(errors="replace")] = value.decode(errors="replace")
        return out


def processes():
    """{pid: Proc} of this user's processes now."""
    me, out = os.getuid(), {}
    for entry in os.listdir("/proc"):
        if not entry.isdigit():
            continue
        try:
            if os.stat(f"/proc/{entry}").st_uid != me:
                continue
            with open(f"/proc/{entry}/stat", "rb") as f:
                fields = f.read().rsplit(b")", 1)[1].split()
        except (OSError, IndexError):
            continue
        # after the command's ")": state(3) ppid(4) ... starttime(22), numbered from 1
        out[int(entry)] = Proc(int(entry), int(fields[1]), fields[0].decode(), int(fields[19]))
    return out


def ancestors(pid, table):
    """The pids above ``pid`` up to init, nearest first."""
    out, seen = [], set()
    while pid in table and pid not in seen and pid > 1:
        seen.add(pid)
        pid = table[pid].ppid
        out.append(pid)
    return out


def tests_processes(token, table=None, before=None):
    """The live processes of ``table`` (default: now) that carry ``token`` or descend from this
    (pytest's) process, other than pytest itself; with ``before`` (a set of idents), only
    those started since."""
    table = processes() if table is None else table
    me = os.getpid()
    out = []
    for proc in table.values():
        if proc.pid == me or not proc.alive or (before is not None and proc.ident in before):
            continue
        if me in ancestors(proc.pid, table) or proc.environ().get(TOKEN) == token:
            out.append(proc)
    return out


def wait_for(predicate, timeout_s, what, poll_s=0.1):
    """Polls ``predicate`` until it returns something truthy (returned); AssertionError with
    ``what`` after ``timeout_s`` (a guard against hanging, generous by design)."""
    deadline = time.monotonic() + timeout_s
    while True:
        value = predicate()
        if value:
            return value
        if time.monotonic() > deadline:
            raise AssertionError(f"gave up waiting for {what} after {timeout_s:g} s")
        time.sleep(poll_s)


def shepherds(token):
    """The live shepherd processes (one per run under way) of this test's experiments."""
    return [p for p in tests_processes(token)
            if "epuck_vrep_compat.experiment.shepherd" in p.cmdline()]


# --- the CLI -----------------------------------------------------------------------------------
def environment(tmp_path, **extra):
    """The test's environment for the CLI: the sourced workspace's, /usr/bin first (another
    python3 may be first on PATH), ROS_HOME and TMPDIR in the test's folder (the runs' folders
    go there: those of runs whose worker died or was interrupted are removed only by a later
    run's sweep), no master of its own."""
    env = dict(os.environ)
    env["PATH"] = "/usr/bin:/bin:" + env.get("PATH", "")
    env["ROS_HOME"] = str(tmp_path / "ros_home")
    os.makedirs(tmp_path / "tmp", exist_ok=True)
    env["TMPDIR"] = str(tmp_path / "tmp")
    env.pop("ROS_MASTER_URI", None)
    env.update({k: str(v) for k, v in extra.items()})
    return env


def command(spec, out, *options):
    return ["rosrun", "epuck_vrep_compat", "experiment", "run", spec, "--out", str(out),
            *[str(o) for o in options]]


def start(args, tmp_path, env=None):
    """The CLI (or any command) started in a session of its own, output to files."""
    log = tmp_path / f"cli-{time.monotonic_ns()}"
    stdout, stderr = open(f"{log}.out", "w+"), open(f"{log}.err", "w+")
    proc = subprocess.Popen(args, cwd=str(tmp_path), env=env or environment(tmp_path),
                            stdout=stdout, stderr=stderr, text=True, start_new_session=True,
                            preexec_fn=_terminal_signals)
    proc.files = (stdout, stderr)
    return proc


def _terminal_signals():
    """In the child before exec: SIGINT and SIGQUIT as a terminal's shell leaves them. A test
    run started in the background of a non-interactive shell (``pytest ... &``) inherits them
    ignored, and Python then never raises KeyboardInterrupt: Ctrl-C would test nothing."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)
    signal.signal(signal.SIGQUIT, signal.SIG_DFL)


def finish(proc, timeout_s=CLI_TIMEOUT_S):
    """Waits for ``proc`` (from ``start``); returns (exit status, stdout, stderr). Past the
    guard time its process group is interrupted, then killed, and the test fails."""
    timed_out = False
    try:
        proc.wait(timeout=timeout_s)
    except subprocess.TimeoutExpired:
        timed_out = True
        for sig, grace in ((signal.SIGINT, 30), (signal.SIGKILL, 10)):
            try:
                os.killpg(proc.pid, sig)
            except ProcessLookupError:
                break
            try:
                proc.wait(timeout=grace)
                break
            except subprocess.TimeoutExpired:
                continue
    texts = []
    for f in proc.files:
        f.flush()
        f.seek(0)
        texts.append(f.read())
        f.close()
    if timed_out:
        raise AssertionError(f"{proc.args} did not end within {timeout_s} s\n"
                             f"stdout:\n{texts[0][-3000:]}\nstderr:\n{texts[1][-3000:]}")
    return proc.returncode, texts[0], texts[1]


def stop(proc, sig=signal.SIGTERM, grace_s=60):
    """Ends ``proc`` (from ``start``) and its process group, quietly: ``sig`` to the process,
    then SIGKILL to its group after ``grace_s``; returns its exit status."""
    if proc.poll() is None:
        proc.send_signal(sig)
        try:
            proc.wait(timeout=grace_s)
        except subprocess.TimeoutExpired:
            try:
                os.killpg(proc.pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
            proc.wait(timeout=30)
    for f in proc.files:
        f.close()
    return proc.returncode


def run(args, tmp_path, env=None, timeout_s=CLI_TIMEOUT_S):
    return finish(start(args, tmp_path, env), timeout_s)


def explain(code, out, err):
    return f"exit status {code}\nstdout:\n{out[-3000:]}\nstderr:\n{err[-5000:]}"


# --- the results folder ------------------------------------------------------------------------
def record(out):
    """The rows of ``runs.jsonl``, in the order they were appended (every line must parse)."""
    with open(os.path.join(out, "runs.jsonl")) as f:
        return [json.loads(line) for line in f if line.strip()]


def csv_rows(out):
    with open(os.path.join(out, "results.csv"), newline="") as f:
        return list(csv.DictReader(f))


def parquet_rows(out):
    return pq.read_table(os.path.join(out, "results.parquet")).to_pylist()


def metrics_of(row):
    return {k: v for k, v in row.items() if k.startswith("metric.")}


def by_key(rows):
    keys = [r["run_key"] for r in rows]
    assert len(keys) == len(set(keys)), f"a run key twice: {sorted(keys)}"
    return {r["run_key"]: r for r in rows}


def describe(rows):
    """The rows, short, for an assertion's message."""
    return "\n".join(f"{r.get('run_key')} {r.get('status')} seed={r.get('seed')} "
                     f"attempts={r.get('attempts')} error={r.get('error')!r} "
                     + " ".join(f"{k}={v}" for k, v in sorted(r.items())
                                if k.startswith("param."))
                     for r in rows)
