"""A pytest plugin (``-p suite.pytest_timing``) that records, per test file, the wall time and
the CPU time of its tests (the test process's own and that of the children it waited for),
and the node ids it collected, into ``$SUITE_TIMING/<worker>.json``. Under pytest-xdist every
worker writes its own file; the runner adds them up. Without SUITE_TIMING it does nothing."""
import json
import os
import resource
import time

import pytest


def _cpu_s():
    own = resource.getrusage(resource.RUSAGE_SELF)
    children = resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + children.ru_utime + children.ru_stime


class Recorder:
    def __init__(self, folder):
        self.folder = folder
        self.files = {}        # test file: [wall_s, cpu_s]
        self.collected = []

    @pytest.hookimpl(trylast=True)
    def pytest_collection_finish(self, session):
        self.collected = [item.nodeid for item in session.items]

    @pytest.hookimpl(hookwrapper=True)
    def pytest_runtest_protocol(self, item, nextitem):
        wall, cpu = time.monotonic(), _cpu_s()
        yield
        spent = self.files.setdefault(item.nodeid.split("::")[0], [0.0, 0.0])
        spent[0] += time.monotonic() - wall
        spent[1] += _cpu_s() - cpu

    def pytest_sessionfinish(self, session):
        if session.config.pluginmanager.hasplugin("dsession"):
            return      # the xdist controller: its workers collected and ran the tests
        os.makedirs(self.folder, exist_ok=True)
        name = os.environ.get("PYTEST_XDIST_WORKER", "main")
        with open(os.path.join(self.folder, f"{name}.json"), "w", encoding="utf-8") as f:
            json.dump({"files": self.files, "collected": self.collected}, f)


def pytest_configure(config):
    folder = os.environ.get("SUITE_TIMING")
    if folder:
        config.pluginmanager.register(Recorder(folder), "suite_timing_recorder")
