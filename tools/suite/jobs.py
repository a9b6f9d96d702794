"""One job of the suite: a command with its own log, its own ROS home and its own results,
run as a process group of its own, measured in wall time and CPU time.

CPU time: where this user may make a cpuacct control group (root, with cgroup v1's cpuacct
mounted, as on Debian's and CI's machines here), every process the job starts is counted,
including those that outlive their parents (a master that roslaunch leaves to init); else
the job and the descendants it waited for (``wait4``), which misses those."""
import os
import signal
import subprocess
import time

CPUACCT = "/sys/fs/cgroup/cpuacct"


class CpuAccount:
    """A cpuacct group of its own for one job's processes; ``None``-like when not allowed."""

    def __init__(self, name):
        self.path = os.path.join(CPUACCT, f"evc_suite_{os.getpid()}_{name}")
        try:
            os.makedirs(self.path)
        except OSError:
            self.path = None

    def join(self):
        """In the job's process, before exec: it and everything it starts count here."""
        if self.path:
            with open(os.path.join(self.path, "tasks"), "w") as f:
                f.write(str(os.getpid()))

    def used_s(self):
        if not self.path:
            return None
        with open(os.path.join(self.path, "cpuacct.usage")) as f:
            return int(f.read()) / 1e9

    def close(self):
        """Remove the group once empty (a process still in it keeps it; it is counted)."""
        if self.path:
            try:
                os.rmdir(self.path)
            except OSError:
                pass


def sweep_accounts():
    """Remove this run's cpuacct groups that were not yet empty when their jobs ended."""
    prefix = f"evc_suite_{os.getpid()}_"
    try:
        names = os.listdir(CPUACCT)
    except OSError:
        return
    for name in names:
        if name.startswith(prefix):
            try:
                os.rmdir(os.path.join(CPUACCT, name))
            except OSError:
                pass


class Job:
    """A command the scheduler runs. ``tier`` and ``name`` label it (``name`` is unique in a
    run); ``files`` are the test files it covers (for the timing table); ``share`` is the cores
    it keeps busy on average, ``wall_s`` its expected wall time (both from remembered costs);
    ``alone`` asks for the machine to itself."""

    def __init__(self, tier, name, argv, results, files=(), alone=False, env=None):
        self.tier, self.name, self.argv = tier, name, list(argv)
        self.files = list(files)
        self.alone = alone
        self.extra_env = dict(env or {})
        self.log = os.path.join(results, "logs", f"{name}.log")
        self.ros_home = os.path.join(results, "ros_home", name)
        self.share, self.wall_s = 1.0, 60.0
        self.fixed_share = None     # cores it keeps busy whatever it measured last
        self.ok_statuses = {0}      # pytest's 5 ("no tests collected") is fine under -k
        self.status = None          # exit status once ended; "hung" when stopped for hanging
        self.started = self.ended = None
        self.cpu_s = 0.0
        self._proc = None
        self._pgid = None
        self._account = None
        self._log_file = None

    @property
    def elapsed_s(self):
        return (self.ended or time.monotonic()) - self.started if self.started else 0.0

    @property
    def passed(self):
        return self.status in self.ok_statuses

    def environment(self):
        env = dict(os.environ)
        env.update(self.extra_env)
        env["ROS_HOME"] = self.ros_home
        env["ROS_LOG_DIR"] = os.path.join(self.ros_home, "log")
        return env

    def start(self, cwd):
        os.makedirs(os.path.dirname(self.log), exist_ok=True)
        os.makedirs(os.path.join(self.ros_home, "log"), exist_ok=True)
        self._log_file = open(self.log, "wb")
        self._account = CpuAccount(self.name)
        self.started = time.monotonic()
        self._proc = subprocess.Popen(self.argv, cwd=cwd, env=self.environment(),
                                      stdin=subprocess.DEVNULL, stdout=self._log_file,
                                      stderr=subprocess.STDOUT, start_new_session=True,
                                      preexec_fn=self._account.join)
        self._pgid = self._proc.pid

    def poll(self):
        """True once the job has ended (its status and CPU time are then set)."""
        if self._proc is None:
            return self.status is not None
        pid, wait_status, usage = os.wait4(self._proc.pid, os.WNOHANG)
        if pid == 0:
            return False
        self.ended = time.monotonic()
        self.status = os.waitstatus_to_exitcode(wait_status)
        self._proc.returncode = self.status
        self._proc = None
        self._log_file.close()
        self._signal_group(signal.SIGKILL)   # whatever the job left behind in its group
        counted = self._account.used_s()
        self.cpu_s = counted if counted is not None else usage.ru_utime + usage.ru_stime
        self._account.close()
        return True

    def _signal_group(self, sig):
        try:
            os.killpg(self._pgid, sig)
        except (ProcessLookupError, PermissionError):
            pass

    def stop(self):
        """End a job still running (the run was interrupted, or the job hung): its whole group,
        politely first, as Ctrl-C would."""
        for sig, wait_s in ((signal.SIGINT, 10.0), (signal.SIGTERM, 5.0), (signal.SIGKILL, 5.0)):
            if self._proc is None:
                return
            self._signal_group(sig)
            deadline = time.monotonic() + wait_s
            while time.monotonic() < deadline:
                if self.poll():
                    return
                time.sleep(0.1)

    def tail(self, lines=40):
        try:
            with open(self.log, "rb") as f:
                text = f.read().decode("utf-8", "replace")
        except OSError:
            return ""
        return "\n".join(text.splitlines()[-lines:])
