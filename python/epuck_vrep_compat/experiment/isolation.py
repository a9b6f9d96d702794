"""What keeps runs apart and leaves nothing behind: a free master port per run, its own
``ROS_HOME``, loopback-only networking, and processes found by a marker, never by name.

Every process a run starts inherits ``EVC_EXPERIMENT_MARKER`` (the experiment's) and
``EVC_RUN_MARKER`` (the run's) in its environment; roslaunch hands its environment to every
node it starts, including the master. ``processes_marked`` finds them through ``/proc`` (own
user only), so a clean-up touches exactly what this experiment started: never another
user's master, never another experiment's run (``pkill rosmaster`` would).
"""
import os
import signal
import socket
import time

EXPERIMENT_MARKER = "EVC_EXPERIMENT_MARKER"
RUN_MARKER = "EVC_RUN_MARKER"


def free_port():
    """A TCP port free on loopback now (the master binds it a moment later; a clash is
    detected by the run and retried)."""
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def run_environment(base_env, port, ros_home, network, experiment_marker, run_marker):
    """The environment of one run: its own master URI, ROS_HOME and log folder; on
    ``loopback`` every node and the master bind 127.0.0.1 only (ROS_IP is what rospy and
    roscpp read for that)."""
    env = dict(base_env)
    for key in ("ROS_IP", "ROS_HOSTNAME", "ROS_NAMESPACE"):
        env.pop(key, None)
    host = "127.0.0.1" if network == "loopback" else socket.gethostname()
    if network == "loopback":
        env["ROS_IP"] = "127.0.0.1"
    env["ROS_MASTER_URI"] = f"http://{host}:{port}"
    env["ROS_HOME"] = ros_home
    env["ROS_LOG_DIR"] = os.path.join(ros_home, "log")
    env[EXPERIMENT_MARKER] = experiment_marker
    env[RUN_MARKER] = run_marker
    env["PYTHONUNBUFFERED"] = "1"
    return env


def processes_marked(name, value):
    """Pids of this user's processes whose environment has ``name=value``."""
    needle = f"{name}={value}".encode()
    me, found = os.getuid(), []
    for entry in os.listdir("/proc"):
        if not entry.isdigit() or int(entry) == os.getpid():
            continue
        try:
            if os.stat(f"/proc/{entry}").st_uid != me:
                continue
            with open(f"/proc/{entry}/environ", "rb") as f:
                if needle in f.read().split(b"\0"):
                    found.append(int(entry))
        except OSError:
            continue                     # gone, or not ours to read
    return found


def terminate(pids, grace_s=5.0):
    """SIGTERM, then SIGKILL after ``grace_s`` for those still there; returns the pids that
    had to be killed."""
    for sig in (signal.SIGTERM, signal.SIGKILL):
        alive = [p for p in pids if _alive(p)]
        for p in alive:
            try:
                os.kill(p, sig)
            except OSError:
                pass
        if sig == signal.SIGKILL:
            return alive
        deadline = time.monotonic() + grace_s
        while time.monotonic() < deadline and any(_alive(p) for p in alive):
            time.sleep(0.05)
    return []


def sweep(name, value, grace_s=5.0):
    """Ends every process marked ``name=value``; returns how many were still there."""
    pids = processes_marked(name, value)
    terminate(pids, grace_s)
    return len(pids)


def _alive(pid):
    return process_identity(pid) is not None


def process_identity(pid):
    """[pid, start time in clock ticks since boot] of a live process (a pid alone is reused),
    or None."""
    try:
        with open(f"/proc/{pid}/stat", "rb") as f:
            fields = f.read().rsplit(b")", 1)[1].split()
        if fields[0] in (b"Z", b"X"):             # a zombie has ended; its parent reaps it
            return None
        return [int(pid), int(fields[19])]        # field 22 of proc(5), counted after comm
    except (OSError, IndexError, ValueError):
        return None
