"""The runner behind tools/test (tools/suite), on small real processes: jobs side by side within
the cores, a job that asks to be alone runs alone, a hung job is stopped, a failure prints its
log's tail; the pytest plugin's records under pytest-xdist; the summary's counts (fewer run
than defined, a skip, a collection error: each fails the run); the timing table."""
import json
import os
import subprocess
import sys
import textwrap
import time

import pytest

from repo import REPO

sys.path.insert(0, os.path.join(REPO, "tools"))
from suite import jobs, plan, scheduler, summary, timing  # noqa: E402


def sleeper(results, name, seconds, share=1.0, alone=False, status=0):
    job = jobs.Job("rostest", name, ["/bin/sh", "-c", f"echo start {name}; sleep {seconds}; "
                                     f"echo end {name}; exit {status}"], str(results),
                   alone=alone)
    job.share, job.wall_s = share, seconds
    return job


def overlaps(ended):
    """Pairs of jobs whose runs overlapped in time."""
    return {(a.name, b.name) for a in ended for b in ended
            if a.name < b.name and a.started < b.ended and b.started < a.ended}


def test_jobs_run_side_by_side_within_the_cores(tmp_path):
    said = []
    batch = [sleeper(tmp_path, f"j{i}", 1.0, share=1.0) for i in range(4)]
    ended = scheduler.run(batch, str(tmp_path), cores=2, say=said.append)
    assert all(j.passed for j in ended)
    # 2 cores x 1.25 = 2.5: two jobs of one core each at a time, never three
    for job in ended:
        at_once = [o for o in ended if o.started <= job.started < o.ended]
        assert len(at_once) <= 2
    assert overlaps(ended), "nothing ran side by side"
    assert any("-- j0: passed" in line for line in said)


def test_a_job_that_asks_to_be_alone_runs_alone(tmp_path):
    batch = [sleeper(tmp_path, "a", 0.6, share=0.1), sleeper(tmp_path, "b", 0.6, share=0.1),
             sleeper(tmp_path, "lone", 0.6, share=0.1, alone=True),
             sleeper(tmp_path, "c", 0.6, share=0.1)]
    ended = scheduler.run(batch, str(tmp_path), cores=2, say=lambda s: None)
    assert all(j.passed for j in ended)
    assert not [pair for pair in overlaps(ended) if "lone" in pair]
    assert overlaps(ended)


def test_a_failure_prints_the_tail_of_its_log(tmp_path):
    said = []
    ended = scheduler.run([sleeper(tmp_path, "bad", 0.1, status=3)], str(tmp_path), 2,
                          said.append)
    assert ended[0].status == 3 and not ended[0].passed
    text = "\n".join(said)
    assert "bad: FAILED (exit status 3)" in text and "end bad" in text


def test_a_hung_job_is_stopped_with_its_whole_group(tmp_path, monkeypatch):
    monkeypatch.setattr(scheduler, "HANG_S", 1.0)
    marker = tmp_path / "child.pid"
    job = jobs.Job("rostest", "hang", ["/bin/sh", "-c", f"sleep 300 & echo $! > {marker}; wait"],
                   str(tmp_path))
    ended = scheduler.run([job], str(tmp_path), 2, lambda s: None)
    assert ended[0].status == "hung" and not ended[0].passed
    child = int(marker.read_text())
    deadline = time.monotonic() + 10.0      # SIGKILL is delivered, not awaited, by killpg
    while not gone(child) and time.monotonic() < deadline:
        time.sleep(0.05)
    assert gone(child)


def gone(pid):
    """The process has ended (a zombie not yet reaped by its new parent counts as ended)."""
    try:
        with open(f"/proc/{pid}/stat", encoding="utf-8") as f:
            return f.read().rsplit(")", 1)[1].split()[0] == "Z"
    except FileNotFoundError:
        return True


def test_each_job_has_its_own_ros_home_and_log(tmp_path):
    job = jobs.Job("rostest", "home", ["/bin/sh", "-c", 'echo "$ROS_HOME $ROS_LOG_DIR"'],
                   str(tmp_path))
    scheduler.run([job], str(tmp_path), 2, lambda s: None)
    home = str(tmp_path / "ros_home" / "home")
    assert job.tail().strip() == f"{home} {home}/log"
    assert os.path.isdir(f"{home}/log")


def test_cpu_time_counts_the_jobs_children(tmp_path):
    burn = f"{sys.executable} -c 'import time; t = time.process_time()\nwhile time.process_time() - t < 0.5: pass'"
    job = jobs.Job("unit", "burn", ["/bin/sh", "-c", f"{burn}; true"], str(tmp_path))
    scheduler.run([job], str(tmp_path), 2, lambda s: None)
    assert job.cpu_s >= 0.45


def test_cpu_time_counts_a_process_its_parent_left_behind(tmp_path):
    """A master that roslaunch leaves to init still ran for the job: counted when the runner
    may make a cpuacct group (root here and in CI), else not (wait4 cannot see it)."""
    burn = f"{sys.executable} -c 'import time; t = time.process_time()\nwhile time.process_time() - t < 0.5: pass'"
    done = tmp_path / "burnt"
    job = jobs.Job("unit", "orphan", ["/bin/sh", "-c", f"({burn}; touch {done}) & "
                                      f"while [ ! -e {done} ]; do sleep 0.05; done; exit 0"],
                   str(tmp_path))
    scheduler.run([job], str(tmp_path), 2, lambda s: None)
    counted = jobs.CpuAccount("probe")
    if counted.path:
        counted.close()
        assert job.cpu_s >= 0.45
    else:
        assert job.cpu_s < 0.45


def write_tests(folder):
    folder.mkdir()
    (folder / "test_a.py").write_text(textwrap.dedent("""
        import time
        def test_one():
            time.sleep(0.2)
        def test_two():
            pass
    """))
    (folder / "test_b.py").write_text("def test_three():\n    pass\n")
    return folder


def run_pytest(tmp_path, tests, extra=()):
    results = tmp_path / "results"
    the_plan = plan.Plan(str(tmp_path), str(results), {}, cores=2)
    job = the_plan._pytest("unit", "pytest-unit", [str(tests)], extra)
    env = dict(job.environment(), PYTHONPATH=os.path.join(REPO, "tools"))
    proc = subprocess.run(job.argv, cwd=tmp_path, env=env, capture_output=True, text=True)
    os.makedirs(results, exist_ok=True)
    summary.write_selection(str(results), [job])
    return proc, results, job


def summarise(repo, results):
    """(the summary's status, its closing line)."""
    said = []
    status = summary.main(str(repo), str(results), said.append)
    return status, said[-1]


@pytest.mark.parametrize("workers", [1, 2])
def test_the_plugin_records_files_and_collected_tests(tmp_path, workers):
    tests = write_tests(tmp_path / "t")
    extra = ["-n", str(workers), "--dist", "loadfile"] if workers > 1 else []
    proc, results, job = run_pytest(tmp_path, tests, extra)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert summary.pytest_collected(str(results), "pytest-unit") == 3
    spent = timing.file_times(job, str(results))
    a = [v for k, v in spent.items() if k.endswith("test_a.py")][0]
    assert a[0] >= 0.19 and len(spent) == 2
    assert summarise(tmp_path, results) == (0, "total: 3 passed, 0 failed")


def test_a_skipped_test_fails_the_summary(tmp_path):
    tests = write_tests(tmp_path / "t")
    (tests / "test_c.py").write_text("import pytest\ndef test_s():\n    pytest.skip('no')\n")
    _, results, _ = run_pytest(tmp_path, tests)
    assert summarise(tmp_path, results) == (1, "total: 3 passed, 1 failed")


def test_a_file_that_cannot_be_imported_fails_the_run(tmp_path):
    tests = write_tests(tmp_path / "t")
    (tests / "test_d.py").write_text("import no_such_module_here\n")
    proc, results, _ = run_pytest(tmp_path, tests)
    assert proc.returncode != 0
    assert summarise(tmp_path, results)[0] == 1


def test_a_rostest_that_ran_fewer_tests_than_it_defines_fails(tmp_path):
    os.makedirs(tmp_path / "test" / "rostest")
    (tmp_path / "test/rostest/x.test").write_text(
        '<launch><test test-name="client" pkg="p" type="client.py"/></launch>')
    (tmp_path / "test/rostest/client.py").write_text(
        "class T:\n    def test_a(self):\n        pass\n    def test_b(self):\n        pass\n")
    results = tmp_path / "results"
    os.makedirs(results / "rostest" / "x" / "epuck_vrep_compat")
    (results / "rostest/x/epuck_vrep_compat/rosunit-client.xml").write_text(
        '<testsuite><testcase name="test_a"/></testsuite>')
    job = jobs.Job("rostest", "rostest-x", ["true"], str(results), files=["test/rostest/x.test"])
    summary.write_selection(str(results), [job])
    said = []
    assert summary.main(str(tmp_path), str(results), said.append) == 1
    assert "rostest x.test client: 1 run of 2 defined, 0 failed, 0 skipped" in said
    assert said[-1] == "total: 1 passed, 1 failed"


def test_an_empty_result_file_counts_as_nothing_run(tmp_path):
    (tmp_path / "gtest-core_cpp_r_x_test.xml").write_text("")
    os.makedirs(tmp_path / "test/core_cpp/r")
    (tmp_path / "test/core_cpp/r/x_test.cpp").write_text("TEST(A, b) {}\n")
    job = jobs.Job("core_cpp", "gtest-core_cpp_r_x_test", ["true"], str(tmp_path),
                   files=["test/core_cpp/r/x_test.cpp"])
    summary.write_selection(str(tmp_path), [job])
    assert summarise(tmp_path, tmp_path) == (1, "total: 0 passed, 1 failed")


def test_the_timing_table_lists_tiers_and_the_slowest_files(tmp_path):
    batch = [sleeper(tmp_path, "slow", 0.5), sleeper(tmp_path, "fast", 0.1)]
    for job, name in zip(batch, ("test/rostest/slow.test", "test/rostest/fast.test")):
        job.files = [name]
    ended = scheduler.run(batch, str(tmp_path), 2, lambda s: None)
    text = timing.write(str(tmp_path), ended, 2, 0.6, stress=False)
    rows = [line for line in text.splitlines() if line.startswith("| test/")]
    assert rows[0].startswith("| test/rostest/slow.test | rostest |")
    assert "| rostest | 2 |" in text
    data = json.loads((tmp_path / "timing.json").read_text())
    assert data["files"][0]["file"] == "test/rostest/slow.test"


def test_remembered_costs_set_each_jobs_share(tmp_path):
    job = jobs.Job("rostest", "rostest-x", ["true"], str(tmp_path))
    timing.apply_costs([job], {"rostest-x": (40.0, 10.0)}, cores=2)
    assert job.wall_s == 40.0 and job.share == pytest.approx(0.25)
    timing.apply_costs([job], {"rostest-x": (10.0, 50.0)}, cores=2)
    assert job.share == 2.0


def test_k_selects_gtest_and_rostest_names_with_pytests_expressions():
    assert plan.matches_k("fuzz and not cell", "vrep_fuzz")
    assert not plan.matches_k("fuzz and not cell", "vrep_fuzz_cell")
    assert plan.matches_k(None, "anything")


def test_a_whole_file_replaces_its_single_tests():
    assert plan.whole_files_first(["f.py::a", "f.py", "g.py::b"]) == ["f.py", "g.py::b"]
