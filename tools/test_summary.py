#!/usr/bin/python3
"""Count what every test tier ran, check it against what exists, print the closing line.

A tier that ran fewer tests than it defines (a rostest that never started, a test file pytest
did not collect) or that skipped any test fails the run, so nothing passes silently.
"""
import glob
import os
import re
import subprocess
import sys
import xml.etree.ElementTree as ET

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def junit_counts(path):
    """(tests, failures, skipped) of one JUnit XML file, counted from its test cases."""
    root = ET.parse(path).getroot()
    cases = list(root.iter("testcase"))
    failed = sum(1 for c in cases if c.find("failure") is not None or c.find("error") is not None)
    skipped = sum(1 for c in cases if c.find("skipped") is not None)
    return len(cases), failed, skipped


def expected_pytest(tier):
    """The number of tests pytest collects in test/<tier>; None when it cannot collect them
    all (an import error in a conftest or a test file), which fails the tier: else a tier
    that cannot even be collected would count as 0 run of 0 defined."""
    proc = subprocess.run([sys.executable, "-m", "pytest", "--collect-only", "-q",
                           "-p", "no:cacheprovider", os.path.join(REPO, "test", tier)],
                          capture_output=True, text=True, cwd=REPO)
    count = sum(1 for line in proc.stdout.splitlines() if "::" in line)
    if proc.returncode != 0 or count == 0:
        print(f"{tier}: pytest could not collect its tests (exit status {proc.returncode}, "
              f"{count} collected)\n" + "\n".join(proc.stdout.splitlines()[-15:]))
        return None
    return count


def gtest_cases(source):
    """The TEST/TEST_F cases a gtest source file defines."""
    return len(re.findall(r"^TEST(_F)?\(", open(source, encoding="utf-8").read(), re.M))


def expected_core_cpp():
    """{test binary name: number of TEST/TEST_F cases} of the core's gtest files, one folder a
    room (test/core_cpp/<room>/<name>_test.cpp, built as core_cpp_<room>_<name>_test). Found at
    any depth: one outside a room's folder, which CMakeLists.txt refuses, counts as not run."""
    expected = {}
    root = os.path.join(REPO, "test", "core_cpp")
    for source in sorted(glob.glob(os.path.join(root, "**", "*_test.cpp"), recursive=True)):
        room = os.path.basename(os.path.dirname(source))
        name = f"core_cpp_{room}_" + os.path.basename(source)[:-len(".cpp")]
        expected[name] = gtest_cases(source)
    return expected


def expected_rostest():
    """{(launch file, test name): number of test cases} for every <test> of every .test file:
    the test_* methods of a python client, the TEST/TEST_F cases of a gtest client (source
    test/rostest_cpp/<type>.cpp), one for an hztest."""
    expected = {}
    launches = sorted(glob.glob(os.path.join(REPO, "test", "rostest", "*.test"))
                      + glob.glob(os.path.join(REPO, "test", "rostest_cpp", "*.test")))
    for launch in launches:
        text = open(launch, encoding="utf-8").read()
        for tag in re.findall(r"<test\b[^>]*>", text):
            name = re.search(r'test-name="([^"]+)"', tag).group(1)
            test_type = re.search(r'type="([^"]+)"', tag).group(1)
            cpp = os.path.join(REPO, "test", "rostest_cpp", test_type + ".cpp")
            if test_type == "hztest":
                count = 1
            elif os.path.exists(cpp):
                count = gtest_cases(cpp)
            else:
                script = os.path.join(REPO, "test", "rostest", test_type)
                count = len(re.findall(r"^\s+def test_", open(script, encoding="utf-8").read(),
                                       re.M))
            expected[(os.path.basename(launch), name)] = count
    return expected


class Tally:
    """Passed and failed over every tier; ``ok`` while each ran all it defines, none failed
    or skipped."""

    def __init__(self):
        self.ok = True
        self.passed = self.failed = 0

    def add(self, label, path, want):
        """One result file (a missing one: nothing ran) against the ``want`` tests defined
        (None: unknown, the tier's tests could not be collected: a failure)."""
        tests, fails, skipped = junit_counts(path) if os.path.exists(path) else (0, 0, 0)
        print(f"{label}: {tests} run of {'?' if want is None else want} defined, {fails} "
              f"failed, {skipped} skipped")
        self.ok &= want is not None and tests == want and fails == 0 and skipped == 0
        self.passed += tests - fails - skipped
        self.failed += fails + skipped + (1 if want is None else max(0, want - tests))


def main(results):
    tally = Tally()
    for tier in ("core", "unit", "install", "experiment"):
        path = os.path.join(results, f"pytest-{tier}.xml")
        if not os.path.exists(path):
            print(f"{tier}: no results (pytest did not run)")
        tally.add(tier, path, expected_pytest(tier))
    for name, want in expected_core_cpp().items():
        tally.add(f"core_cpp {name}", os.path.join(results, f"gtest-{name}.xml"), want)
    for (launch, name), want in expected_rostest().items():
        tally.add(f"rostest {launch} {name}",
                  os.path.join(results, "rostest", "epuck_vrep_compat", f"rosunit-{name}.xml"),
                  want)
    print(f"total: {tally.passed} passed, {tally.failed} failed")
    return 0 if tally.ok else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1]))
