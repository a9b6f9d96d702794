"""The manifests are complete and tools/setup installs what they declare: every rosdep key of
package.xml and vrep_common/package.xml maps to Debian packages (or a pip package) through
tools/dependencies.yaml, and every one of those is in tools/setup's apt_packages (or its pip
install). A dependency added to a manifest but not to the set-up, or dropped from the set-up,
fails here rather than on a new user's machine."""
import os
import re
import subprocess
import xml.etree.ElementTree as ET

import pytest
import yaml

from repo import REPO

MANIFESTS = ("package.xml", "vrep_common/package.xml")
DEPENDENCY_TAGS = ("depend", "build_depend", "build_export_depend", "buildtool_depend",
                   "exec_depend", "test_depend", "doc_depend")


def manifest_keys(path):
    root = ET.parse(os.path.join(REPO, path)).getroot()
    return {element.text.strip() for tag in DEPENDENCY_TAGS for element in root.iter(tag)}


def setup_text():
    with open(os.path.join(REPO, "tools", "setup")) as f:
        return f.read()


def apt_packages(text):
    """The words of the ``apt_packages=( ... )`` array, as bash reads it (comments dropped)."""
    block = re.search(r"^apt_packages=\((.*?)^\)", text, re.S | re.M)
    assert block, "tools/setup has no apt_packages=( ... ) array"
    words = subprocess.run(["bash", "-c", f"a=({block.group(1)}); printf '%s\\n' \"${{a[@]}}\""],
                           capture_output=True, text=True, check=True).stdout.split()
    return set(words)


def table():
    with open(os.path.join(REPO, "tools", "dependencies.yaml")) as f:
        return yaml.safe_load(f)


def missing_from_setup(keys, deps, apt, setup):
    """Every way a key can fail to be installed by the set-up, as messages."""
    problems = []
    for key in sorted(keys):
        if key not in deps:
            problems.append(f"rosdep key '{key}' is not in tools/dependencies.yaml")
            continue
        target = deps[key]
        if target == "workspace":
            if not os.path.isfile(os.path.join(REPO, key, "package.xml")):
                problems.append(f"'{key}' is marked workspace but {key}/package.xml is missing")
        elif isinstance(target, dict):
            name = target["pip"]
            if not re.search(rf"pip\" install .*\b{re.escape(name)}\b", setup) and \
                    not re.search(rf"\b{re.escape(name)}_version=", setup):
                problems.append(f"'{key}' needs pip package {name}, which tools/setup does "
                                "not install")
        else:
            for package in target:
                if package not in apt:
                    problems.append(f"'{key}' needs Debian package {package}, missing from "
                                    "tools/setup's apt_packages")
    return problems


@pytest.mark.parametrize("manifest", MANIFESTS)
def test_every_manifest_key_is_installed_by_setup(manifest):
    text = setup_text()
    problems = missing_from_setup(manifest_keys(manifest), table(), apt_packages(text), text)
    assert not problems, "\n".join(problems)


def test_every_table_entry_is_used_by_a_manifest():
    used = set().union(*(manifest_keys(m) for m in MANIFESTS))
    assert not set(table()) - used, "stale keys in tools/dependencies.yaml"


def test_the_check_fails_when_a_package_leaves_the_setup():
    """The check above is not vacuous: drop one Debian package or one key and it complains."""
    text = setup_text()
    apt = apt_packages(text)
    keys = manifest_keys("package.xml")
    assert "libgtest-dev" in apt
    assert missing_from_setup(keys, table(), apt - {"libgtest-dev"}, text) == [
        "'gtest' needs Debian package libgtest-dev, missing from tools/setup's apt_packages"]
    deps = dict(table())
    del deps["rospy"]
    assert missing_from_setup(keys, deps, apt, text) == [
        "rosdep key 'rospy' is not in tools/dependencies.yaml"]
    assert missing_from_setup(keys, table(), apt, text.replace("pybullet", "other")) == [
        "'python3-pybullet-pip' needs pip package pybullet, which tools/setup does not install"]
