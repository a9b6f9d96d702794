"""Count what every job ran, check it against what exists, print the closing line.

A job that ran fewer tests than it defines (a rostest whose node died reports "SUCCESS, 0
tests"; a pytest worker that crashed) or that skipped any test fails the run, so nothing passes
silently. What a job defines: for pytest, the node ids its own processes collected (recorded
by suite.pytest_timing: a file pytest could not import is a collection error and fails the
job); for a gtest binary, the TEST and TEST_F cases of its source; for a rostest file, the
test methods of each of its python clients, the cases of its gtest clients, one per hztest.
The run's jobs are read from ``selection.json`` in the results, so the summary can be printed
again for the last run."""
import glob
import json
import os
import re
import xml.etree.ElementTree as ET

from suite import plan


def junit_counts(path):
    """(tests, failures, skipped) of one JUnit XML file, counted from its test cases."""
    try:
        root = ET.parse(path).getroot()
    except ET.ParseError:
        return 0, 0, 0          # cut short (its writer killed): what it holds did not run
    cases = list(root.iter("testcase"))
    failed = sum(1 for c in cases if c.find("failure") is not None or c.find("error") is not None)
    skipped = sum(1 for c in cases if c.find("skipped") is not None)
    return len(cases), failed, skipped


def gtest_cases(source):
    with open(source, encoding="utf-8") as f:
        return len(re.findall(r"^TEST(_F)?\(", f.read(), re.M))


def pytest_collected(results, name):
    """How many tests the job's pytest processes collected; None if none recorded."""
    ids, found = set(), False
    for path in glob.glob(os.path.join(results, "timing", name, "*.json")):
        with open(path, encoding="utf-8") as f:
            ids.update(json.load(f)["collected"])
        found = True
    return len(ids) if found else None


def rostest_cases(repo, launch):
    """[(test name, number of cases)] for every <test> of a .test file."""
    with open(os.path.join(repo, launch), encoding="utf-8") as f:
        text = f.read()
    cases = []
    for tag in re.findall(r"<test\b[^>]*>", text):
        name = re.search(r'test-name="([^"]+)"', tag).group(1)
        test_type = re.search(r'type="([^"]+)"', tag).group(1)
        cpp = os.path.join(repo, "test", "rostest_cpp", test_type + ".cpp")
        if test_type == "hztest":
            count = 1
        elif os.path.exists(cpp):
            count = gtest_cases(cpp)
        else:
            with open(os.path.join(repo, "test", "rostest", test_type), encoding="utf-8") as f:
                count = len(re.findall(r"^\s+def test_", f.read(), re.M))
        cases.append((name, count))
    return cases


class Tally:
    """Passed and failed over every job; ``ok`` while each ran all it defines, none failed
    or skipped."""

    def __init__(self, say):
        self.ok, self.passed, self.failed, self.say = True, 0, 0, say

    def add(self, label, path, want):
        """One result file (a missing one: nothing ran) against the ``want`` tests defined
        (None: unknown, the job's tests could not be collected: a failure)."""
        tests, fails, skipped = junit_counts(path) if os.path.exists(path) else (0, 0, 0)
        self.say(f"{label}: {tests} run of {'?' if want is None else want} defined, {fails} "
                 f"failed, {skipped} skipped" + ("" if tests or not os.path.exists(path) else
                                                 " (its result file holds no test case)"))
        self.ok &= want is not None and tests == want and fails == 0 and skipped == 0
        self.passed += tests - fails - skipped
        self.failed += fails + skipped + (1 if want is None else max(0, want - tests))


def write_selection(results, jobs):
    with open(os.path.join(results, "selection.json"), "w", encoding="utf-8") as f:
        json.dump([{"tier": j.tier, "name": j.name, "files": j.files} for j in jobs], f,
                  indent=1)


def main(repo, results, say=print):
    """Print each job's count and the closing line; 0 when everything ran and passed."""
    with open(os.path.join(results, "selection.json"), encoding="utf-8") as f:
        jobs = json.load(f)
    tally = Tally(say)
    for job in jobs:
        name, tier = job["name"], job["tier"]
        if tier == "core_cpp":
            tally.add(f"core_cpp {name[len('gtest-'):]}", os.path.join(results, f"{name}.xml"),
                      gtest_cases(os.path.join(repo, job["files"][0])))
        elif tier == "rostest":
            launch = job["files"][0]
            for test_name, want in rostest_cases(repo, launch):
                tally.add(f"rostest {os.path.basename(launch)} {test_name}",
                          os.path.join(plan.rostest_results(results, plan.launch_name(launch)),
                                       "epuck_vrep_compat", f"rosunit-{test_name}.xml"), want)
        else:
            label = name[len("pytest-"):]
            tally.add(label, os.path.join(results, f"{name}.xml"),
                      pytest_collected(results, name))
    say(f"total: {tally.passed} passed, {tally.failed} failed")
    return 0 if tally.ok else 1
