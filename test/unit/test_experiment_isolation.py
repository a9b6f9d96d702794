"""What keeps runs apart and leaves nothing behind, on real processes: a free port, a run's
environment, processes found by their marker (never by name), ended by SIGTERM or, when they
ignore it, by SIGKILL. Every process a test starts is ended by its fixture, pass or fail."""
import os
import signal
import socket
import subprocess
import sys
import time
import uuid

import pytest

from epuck_vrep_compat.experiment import isolation, shepherd

SLEEPER = "import time; time.sleep(60)"
STUBBORN = ("import signal, sys, time; signal.signal(signal.SIGTERM, signal.SIG_IGN); "
            "print('ready', flush=True); time.sleep(60)")


@pytest.fixture
def start():
    """start(code, marker=None) -> Popen of ``python -c code``, with ``EVC_RUN_MARKER=marker``
    in its environment when given; all killed and reaped at the test's end."""
    started = []

    def _start(code, marker=None):
        env = {k: v for k, v in os.environ.items() if k != isolation.RUN_MARKER}
        if marker is not None:
            env[isolation.RUN_MARKER] = marker
        process = subprocess.Popen([sys.executable, "-c", code], env=env,
                                   stdout=subprocess.PIPE, text=True)
        started.append(process)
        return process

    yield _start
    for process in started:
        if process.poll() is None:
            process.kill()
        process.wait()
        process.stdout.close()


def marker():
    return f"test-{uuid.uuid4().hex}"


def test_free_port_is_bindable_on_loopback():
    port = isolation.free_port()
    assert 1024 <= port <= 65535
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
        s.bind(("127.0.0.1", port))


BASE = {"PATH": "/usr/bin", "ROS_IP": "10.0.0.9", "ROS_HOSTNAME": "elsewhere",
        "ROS_NAMESPACE": "/ns", "ROS_MASTER_URI": "http://elsewhere:11311"}


def test_a_loopback_run_environment():
    env = isolation.run_environment(BASE, 12345, "/tmp/run/ros_home", "loopback", "exp", "run")
    assert env == {"PATH": "/usr/bin", "ROS_IP": "127.0.0.1",
                   "ROS_MASTER_URI": "http://127.0.0.1:12345", "ROS_HOME": "/tmp/run/ros_home",
                   "ROS_LOG_DIR": "/tmp/run/ros_home/log", isolation.EXPERIMENT_MARKER: "exp",
                   isolation.RUN_MARKER: "run", "PYTHONUNBUFFERED": "1"}
    assert BASE["ROS_IP"] == "10.0.0.9"                   # the caller's is left as it was


def test_an_all_interfaces_run_environment_sets_no_ros_ip():
    env = isolation.run_environment(BASE, 12345, "/tmp/h", "all", "exp", "run")
    assert not {"ROS_IP", "ROS_HOSTNAME", "ROS_NAMESPACE"} & set(env)
    assert env["ROS_MASTER_URI"] == f"http://{socket.gethostname()}:12345"
    assert (env["ROS_HOME"], env["ROS_LOG_DIR"]) == ("/tmp/h", "/tmp/h/log")


def test_processes_are_found_by_their_marker_only(start):
    mine = marker()
    marked, other, unmarked = start(SLEEPER, mine), start(SLEEPER, marker()), start(SLEEPER)
    found = isolation.processes_marked(isolation.RUN_MARKER, mine)
    assert found == [marked.pid]
    assert other.pid not in found and unmarked.pid not in found
    assert isolation.processes_marked(isolation.RUN_MARKER, marker()) == []


def test_terminate_ends_a_process_with_sigterm(start):
    process = start(SLEEPER)
    began = time.monotonic()
    assert isolation.terminate([process.pid], grace_s=10.0) == []
    assert process.wait(5.0) == -signal.SIGTERM
    assert time.monotonic() - began < 5.0


def test_terminate_kills_one_that_ignores_sigterm_after_the_grace(start):
    process = start(STUBBORN)
    assert process.stdout.readline() == "ready\n"      # its handler is in place
    began = time.monotonic()
    assert isolation.terminate([process.pid], grace_s=0.5) == [process.pid]
    assert process.wait(5.0) == -signal.SIGKILL
    assert time.monotonic() - began >= 0.5


def test_sweep_ends_the_marked_and_counts_them(start):
    mine = marker()
    marked = [start(SLEEPER, mine), start(SLEEPER, mine)]
    bystander = start(SLEEPER)
    assert isolation.sweep(isolation.RUN_MARKER, mine, grace_s=5.0) == 2
    assert [p.wait(5.0) for p in marked] == [-signal.SIGTERM] * 2
    assert bystander.poll() is None
    assert isolation.sweep(isolation.RUN_MARKER, mine, grace_s=5.0) == 0


def test_a_launch_that_outlives_sigint_keeps_its_exit_status():
    """A roslaunch still running after SIGINT's grace (a loaded machine) is ended by SIGTERM,
    and its status is the one recorded: the shepherd's sweep of its other children must not
    reap it first (a timed-out run's row had no exit code beside a CPU hog)."""
    launch = subprocess.Popen([sys.executable, "-c", "import signal, time; "
                               "signal.signal(signal.SIGINT, signal.SIG_IGN); "
                               "print('ready', flush=True); time.sleep(60)"],
                              stdout=subprocess.PIPE, text=True)
    assert launch.stdout.readline().strip() == "ready"
    left, killed = shepherd.end_everything(launch, uuid.uuid4().hex, sigint_grace_s=0.5)
    assert launch.pid in left and killed == []          # SIGTERM was enough
    assert launch.returncode == -signal.SIGTERM
