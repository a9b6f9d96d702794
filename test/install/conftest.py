"""The install tier's set-up: the install space (``catkin_make install``'s ``.ws/install``)
and a clean environment that sees nothing else (``env -i``: only the install space sourced, a
private master on a free port), so nothing of the source tree or the devel space can stand in
for a missing installed file."""
import os
import signal
import subprocess
import tempfile
import time

import pytest

from epuck_vrep_compat.experiment.isolation import free_port
from repo import REPO

INSTALL = os.path.join(REPO, ".ws", "install")
SETUP = os.path.join(INSTALL, "local_setup.bash")


class InstallEnv:
    """Commands run through bash with only the install space sourced, on a private master."""

    def __init__(self, tmp):
        self.port = free_port()
        self.tmp = tmp
        self.env = {
            "HOME": os.environ.get("HOME", "/root"), "PATH": "/usr/bin:/bin", "LANG": "C.UTF-8",
            "ROS_HOME": os.path.join(tmp, "ros_home"), "ROS_LOG_DIR": os.path.join(tmp, "log"),
        }
        self.launches = []

    def _script(self, command):
        return (f"set -e; source {SETUP}; "
                f"export ROS_MASTER_URI=http://127.0.0.1:{self.port}; {command}")

    def run(self, command, timeout=60):
        return subprocess.run(["bash", "-c", self._script(command)], env=self.env, cwd=self.tmp,
                              capture_output=True, text=True, timeout=timeout)

    def launch(self, args):
        log = open(os.path.join(self.tmp, f"launch{len(self.launches)}.log"), "w")
        proc = subprocess.Popen(
            ["bash", "-c", self._script(f"exec roslaunch -p {self.port} {args}")],
            env=self.env, cwd=self.tmp, stdout=log, stderr=subprocess.STDOUT,
            start_new_session=True)
        self.launches.append((proc, log))
        return proc

    def wait_for_message(self, topic, timeout_s=90.0):
        """The first message on a topic (rostopic echo), retried while the graph comes up."""
        deadline = time.monotonic() + timeout_s
        last = None
        while time.monotonic() < deadline:
            for proc, _ in self.launches:
                assert proc.poll() is None, f"roslaunch ended with {proc.returncode}:\n" \
                                            + self.logs()
            try:
                last = self.run(f"rostopic echo -n 1 --noarr {topic}", timeout=20)
            except subprocess.TimeoutExpired:
                continue
            if last.returncode == 0 and last.stdout.strip():
                return last.stdout
            time.sleep(1.0)
        raise AssertionError(f"no message on {topic} within {timeout_s} s: "
                             f"{last.stderr if last else ''}\n{self.logs()}")

    def logs(self):
        text = []
        for _, log in self.launches:
            log.flush()
            with open(log.name) as f:
                text.append(f.read()[-3000:])
        return "\n".join(text)

    def close(self):
        for proc, log in self.launches:
            if proc.poll() is None:
                os.killpg(proc.pid, signal.SIGINT)
                try:
                    proc.wait(timeout=20)
                except subprocess.TimeoutExpired:
                    os.killpg(proc.pid, signal.SIGKILL)
                    proc.wait()
            log.close()


@pytest.fixture(scope="session")
def install_space():
    """The install space's prefix (``.ws/install``), once ``catkin_make install`` made it."""
    assert os.path.isfile(SETUP), f"no install space at {INSTALL}: run catkin_make install"
    return INSTALL


@pytest.fixture
def install_env(install_space):
    """An :class:`InstallEnv` in a temporary folder; its launches ended after the test."""
    with tempfile.TemporaryDirectory() as tmp:
        env = InstallEnv(tmp)
        try:
            yield env
        finally:
            env.close()
