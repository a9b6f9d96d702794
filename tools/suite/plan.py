"""What a run of the suite consists of: the selection (which tiers, which files, ``-k``) turned
into jobs, and what each job is expected to run.

Tiers, in the order they are listed: core and unit (pytest, spread over the cores with
pytest-xdist, a file to a worker), install (``catkin_make install``, then pytest), core_cpp
(one job per gtest binary), experiment (one pytest job per test: each starts its own
masters, Dask and launch trees, and waits on them), rostest (one job per .test file: rostest
starts a master of its own on a free port; the job gets its own ROS_HOME and log folder).
A rostest file that needs the machine to itself says so with ``<!-- suite: alone -->``.
"""
import glob
import os
import re
import sys

from suite.jobs import Job

TIERS = ("core", "unit", "install", "core_cpp", "experiment", "rostest")
XDIST_TIERS = ("core", "unit")
PYTEST = [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider",
          "-p", "suite.pytest_timing", "-o", "junit_family=xunit1"]
ALONE_MARK = re.compile(r"<!--\s*suite:\s*alone\b")


def tier_files(repo, tier):
    """Every test file of a tier, relative to the repository."""
    patterns = {"core": ["test/core/**/test_*.py"], "unit": ["test/unit/**/test_*.py"],
                "install": ["test/install/**/test_*.py"],
                "experiment": ["test/experiment/**/test_*.py"],
                "core_cpp": ["test/core_cpp/**/*_test.cpp"],
                "rostest": ["test/rostest/*.test", "test/rostest_cpp/*.test"]}[tier]
    found = set()
    for pattern in patterns:
        found.update(os.path.relpath(p, repo)
                     for p in glob.glob(os.path.join(repo, pattern), recursive=True))
    return sorted(found)


def tier_of(path):
    """The tier a test path (file, folder or ``file::test``) belongs to, or None."""
    parts = path.split("::")[0].split("/")
    if len(parts) < 2 or parts[0] != "test":
        return None
    return {"rostest_cpp": "rostest"}.get(parts[1], parts[1] if parts[1] in TIERS else None)


def gtest_name(source):
    """test/core_cpp/<room>/<name>_test.cpp is built as core_cpp_<room>_<name>_test."""
    room = os.path.basename(os.path.dirname(source))
    return f"core_cpp_{room}_" + os.path.basename(source)[:-len(".cpp")]


def matches_k(expression, name):
    """``-k`` for what is not pytest (gtest binaries, rostest files): pytest's own expression
    language, each identifier a substring of the name."""
    if not expression:
        return True
    from _pytest.mark.expression import Expression
    return Expression.compile(expression).evaluate(lambda word: word.lower() in name.lower())


class Plan:
    """The jobs of one run and the selection they came from: ``selection`` maps each tier to
    the test paths to run (a file, or ``file::test``), ``k`` is pytest's ``-k``."""

    def __init__(self, repo, results, selection, k=None, cores=2):
        self.repo, self.results, self.k, self.cores = repo, results, k, cores
        self.selection = {tier: whole_files_first(paths) for tier, paths in selection.items()
                          if paths}
        self.jobs = []
        for tier in TIERS:
            if tier in self.selection:
                getattr(self, f"_plan_{tier}")(self.selection[tier])

    def _pytest(self, tier, name, paths, extra=()):
        junit = os.path.join(self.results, f"{name}.xml")
        argv = PYTEST + [f"--junitxml={junit}"] + (["-k", self.k] if self.k else []) + list(extra)
        env = {"SUITE_TIMING": os.path.join(self.results, "timing", name)}
        job = Job(tier, name, argv + list(paths), self.results, files=paths, env=env)
        if self.k:
            job.ok_statuses = {0, 5}
        return job

    def _plan_xdist(self, tier, paths):
        files = {p.split("::")[0] for p in paths}
        workers = min(self.cores, len(files))
        extra = ["-n", str(workers), "--dist", "loadfile"] if workers > 1 else []
        job = self._pytest(tier, f"pytest-{tier}", paths, extra)
        job.fixed_share = float(workers)        # its workers run flat out, whatever it ran last
        self.jobs.append(job)

    def _plan_core(self, paths):
        self._plan_xdist("core", paths)

    def _plan_unit(self, paths):
        self._plan_xdist("unit", paths)

    def _plan_install(self, paths):
        """The install space first (catkin_make install), then its tests, in one job."""
        job = self._pytest("install", "pytest-install", paths)
        build_log = os.path.join(self.results, "logs", "catkin_make_install.log")
        job.argv = ["/bin/bash", "-c",
                    'catkin_make -C .ws install > "$0" 2>&1 || { tail -n 40 "$0"; '
                    'echo "test: catkin_make install failed"; exit 1; }; exec "$@"',
                    build_log] + job.argv
        job.extra_env["ROS_LANG_DISABLE"] = "genlisp"      # as tools/setup builds
        self.jobs.append(job)

    def _plan_core_cpp(self, paths):
        for source in paths:
            name = gtest_name(source)
            if not matches_k(self.k, name):
                continue
            binary = os.path.join(self.repo, ".ws", "devel", "lib", "epuck_vrep_compat", name)
            junit = os.path.join(self.results, f"gtest-{name}.xml")
            argv = ([binary, f"--gtest_output=xml:{junit}"] if os.access(binary, os.X_OK) else
                    ["/bin/sh", "-c", f"echo 'test: {name} was not built (tools/setup)'; exit 1"])
            self.jobs.append(Job("core_cpp", f"gtest-{name}", argv, self.results, files=[source]))

    def _plan_experiment(self, paths):
        """A job per test: each starts its own masters, launch trees and Dask cluster, and
        the tier's largest tests take minutes each, so a file per job would leave a core idle
        at the end while one file's tests ran one after another."""
        for path in paths:
            targets = [path] if "::" in path else module_tests(self.repo, path) or [path]
            for target in targets:
                file, _, test = target.partition("::")
                name = "pytest-experiment-" + os.path.basename(file)[:-len(".py")]
                self.jobs.append(self._pytest("experiment", name + (f"-{test}" if test else ""),
                                              [target]))

    def _plan_rostest(self, paths):
        for launch in paths:
            name = launch_name(launch)
            if not matches_k(self.k, name):
                continue
            # results apart per file: rostest removes a test's old result file by its
            # test-name before it runs it, and two files may use one name (hz_imu)
            argv = ["rostest", f"--results-base-dir={rostest_results(self.results, name)}",
                    "epuck_vrep_compat", os.path.basename(launch)]
            with open(os.path.join(self.repo, launch), encoding="utf-8") as f:
                alone = bool(ALONE_MARK.search(f.read()))
            self.jobs.append(Job("rostest", f"rostest-{name}", argv, self.results,
                                 files=[launch], alone=alone))


def launch_name(launch):
    """A rostest file's name without its folder and ``.test``: its job's and results' name."""
    return os.path.basename(launch)[:-len(".test")]


def rostest_results(results, name):
    """The folder a rostest file's results go to (rostest adds <package>/rosunit-<test>.xml)."""
    return os.path.join(results, "rostest", name)


def module_tests(repo, path):
    """``file::test`` for each test function defined at the top of a test file."""
    with open(os.path.join(repo, path), encoding="utf-8") as f:
        return [f"{path}::{name}" for name in re.findall(r"^def (test_\w+)\(", f.read(), re.M)]


def whole_files_first(paths):
    """Sorted paths without a ``file::test`` whose whole file is there too."""
    paths = set(paths)
    return sorted(p for p in paths if "::" not in p or p.split("::")[0] not in paths)


def full_selection(repo, tiers=TIERS):
    return {tier: tier_files(repo, tier) for tier in tiers}
