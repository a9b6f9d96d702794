"""setup.py lists every package of python/: catkin installs only those, so a package left out
works in the devel space and is missing from the install space."""
import ast
import os

from repo import REPO


def listed_packages():
    tree = ast.parse(open(os.path.join(REPO, "setup.py"), encoding="utf-8").read())
    for node in ast.walk(tree):
        if isinstance(node, ast.keyword) and node.arg == "packages":
            return {elt.value for elt in node.value.elts}
    raise AssertionError("setup.py has no packages=[...]")


def packages_on_disk():
    root = os.path.join(REPO, "python")
    return {os.path.relpath(folder, root).replace(os.sep, ".")
            for folder, _dirs, files in os.walk(root) if "__init__.py" in files}


def test_setup_lists_every_package_and_nothing_else():
    assert listed_packages() == packages_on_disk()
