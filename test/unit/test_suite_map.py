"""test/covers.yaml, the map behind `tools/test --changed`, kept true: every package of the
Python package has a key, every key is a path that exists, every entry names tests that exist;
and the selection it gives for a changed file."""
import os
import subprocess
import sys

import pytest

from repo import REPO

sys.path.insert(0, os.path.join(REPO, "tools"))
from suite import changed, plan  # noqa: E402

COVERS = changed.load_covers(REPO)


def packages():
    root = os.path.join(REPO, changed.PACKAGE)
    return sorted(os.path.relpath(d, REPO) for d, _, files in os.walk(root)
                  if "__init__.py" in files)


def test_every_package_has_a_key_of_its_own():
    missing = [p for p in packages() if p not in COVERS]
    assert not missing, f"test/covers.yaml has no key for {missing}"


@pytest.mark.parametrize("key", sorted(COVERS))
def test_each_key_exists_and_names_tests_that_exist(key):
    assert os.path.exists(os.path.join(REPO, key)), f"{key} is not a path of the repository"
    assert COVERS[key], f"{key} names no tests"
    for target in COVERS[key]:
        found = changed.expand(REPO, target)
        assert found, f"{key}: {target} matches no test file"
        for path in found:
            file, _, test = path.partition("::")
            assert os.path.exists(os.path.join(REPO, file)), f"{key}: {file} does not exist"
            if test:
                with open(os.path.join(REPO, file), encoding="utf-8") as f:
                    assert f"def {test}(" in f.read(), f"{key}: {path} is no test of {file}"


def test_the_most_specific_key_wins():
    covers = {"python/p": ["a"], "python/p/q": ["b"]}
    assert changed.cover_key(covers, "python/p/q/m.py") == "python/p/q"
    assert changed.cover_key(covers, "python/p/m.py") == "python/p"
    assert changed.cover_key(covers, "python/pq/m.py") is None     # a prefix is not a folder


def git(repo, *args):
    subprocess.run(["git", *args], cwd=repo, check=True, capture_output=True)


@pytest.fixture
def checkout(tmp_path):
    """A small repository shaped like ours: a package with two subpackages, tests that import
    them, a covers.yaml; one commit."""
    files = {
        "python/epuck_vrep_compat/__init__.py": "",
        "python/epuck_vrep_compat/learn/__init__.py": "",
        "python/epuck_vrep_compat/learn/env.py": "X = 1\n",
        "python/epuck_vrep_compat/scene/__init__.py": "",
        "test/unit/test_env.py": "from epuck_vrep_compat.learn import env\n",
        "test/unit/test_scene.py": "import epuck_vrep_compat.scene\n",
        "test/core/test_core.py": "",
        "test/rostest/learn.test": "<launch/>\n",
        "test/covers.yaml": "python/epuck_vrep_compat/learn: [test/rostest/learn.test]\n"
                            "docs: [test/unit/test_scene.py]\n",
        "docs/x.md": "",
        "README.md": "",
    }
    for path, text in files.items():
        os.makedirs(tmp_path / os.path.dirname(path), exist_ok=True)
        (tmp_path / path).write_text(text)
    git(tmp_path, "init", "-q")
    git(tmp_path, "add", "-A")
    git(tmp_path, "-c", "user.name=t", "-c", "user.email=t@t", "commit", "-qm", "one")
    return tmp_path


def test_a_changed_module_runs_its_key_and_the_tests_that_import_its_package(checkout):
    (checkout / "python/epuck_vrep_compat/learn/env.py").write_text("X = 2\n")
    picked, why = changed.selection(str(checkout), "HEAD")
    assert picked == {"rostest": ["test/rostest/learn.test"], "unit": ["test/unit/test_env.py"]}
    assert "python/epuck_vrep_compat/learn" in why["python/epuck_vrep_compat/learn/env.py"]


def test_a_changed_test_runs_itself_and_an_untracked_file_counts(checkout):
    (checkout / "test/unit/test_scene.py").write_text("import epuck_vrep_compat.scene  # x\n")
    (checkout / "docs/y.md").write_text("new\n")
    picked, _ = changed.selection(str(checkout), "HEAD")
    assert picked == {"unit": ["test/unit/test_scene.py"]}


def test_a_file_no_key_covers_runs_the_whole_suite(checkout):
    (checkout / "README.md").write_text("changed\n")
    picked, why = changed.selection(str(checkout), "HEAD")
    assert "whole suite" in why["README.md"]
    assert picked["core"] == ["test/core/test_core.py"]
    assert picked["rostest"] == ["test/rostest/learn.test"]


def test_nothing_changed_selects_nothing(checkout):
    assert changed.selection(str(checkout), "HEAD") == ({}, {})


def test_since_a_commit_counts_what_was_committed_after_it(checkout):
    (checkout / "docs/x.md").write_text("changed\n")
    git(checkout, "-c", "user.name=t", "-c", "user.email=t@t", "commit", "-qam", "two")
    assert changed.selection(str(checkout), "HEAD") == ({}, {})
    picked, _ = changed.selection(str(checkout), "HEAD~1")
    assert picked == {"unit": ["test/unit/test_scene.py"]}


def test_tiers_of_paths():
    assert plan.tier_of("test/rostest_cpp/x.test") == "rostest"
    assert plan.tier_of("test/experiment/test_x.py::test_y") == "experiment"
    assert plan.tier_of("test/covers.yaml") is None
    assert plan.tier_of("python/x.py") is None
