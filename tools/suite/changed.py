"""``--changed`` and ``--since REF``: the tests that cover what changed.

What changed: the files that differ from REF (HEAD for ``--changed``) in the working tree, and
the untracked ones. What covers them: test/covers.yaml, a map from paths (a file or a folder)
to test paths; the most specific key containing a changed file wins. A changed test file runs
itself (a helper of a test folder runs that folder's tier). A changed module of the Python
package also runs every core and unit test file that imports its package. A changed file that
no key covers runs the whole suite: better slow than blind."""
import fnmatch
import functools
import os
import subprocess

import yaml

from suite.plan import TIERS, tier_files, tier_of

COVERS = os.path.join("test", "covers.yaml")
PACKAGE = os.path.join("python", "epuck_vrep_compat")


def changed_files(repo, ref):
    def git(*args):
        return subprocess.run(["git", *args], cwd=repo, check=True, capture_output=True,
                              text=True).stdout.split()
    return sorted(set(git("diff", "--name-only", ref, "--")
                      + git("ls-files", "--others", "--exclude-standard")))


def load_covers(repo):
    with open(os.path.join(repo, COVERS), encoding="utf-8") as f:
        return yaml.safe_load(f)


def cover_key(covers, path):
    """The most specific key of ``covers`` that is ``path`` or a folder holding it."""
    keys = [k for k in covers if path == k or path.startswith(k.rstrip("/") + "/")]
    return max(keys, key=len) if keys else None


def expand(repo, target):
    """A covers.yaml target (a test file, ``file::test``, a folder or a glob) as test paths."""
    if "::" in target:
        return [target]
    tier = tier_of(target)
    if tier is None:
        raise ValueError(f"{COVERS}: {target} is not under a test tier's folder")
    return [p for p in tier_files(repo, tier)
            if fnmatch.fnmatch(p, target) or p == target or p.startswith(target.rstrip("/") + "/")]


@functools.lru_cache(maxsize=None)
def _test_texts(repo):
    """(path, text) of every core and unit test file, read once for all changed modules."""
    texts = []
    for tier in ("core", "unit"):
        for test in tier_files(repo, tier):
            with open(os.path.join(repo, test), encoding="utf-8") as f:
                texts.append((test, f.read()))
    return tuple(texts)


def importers(repo, path):
    """Core and unit test files that import the package of a changed module."""
    package = os.path.dirname(os.path.relpath(path, "python")).replace("/", ".")
    return [test for test, text in _test_texts(repo)
            if f"{package} import" in text or f"import {package}" in text or f"{package}." in text]


def selection(repo, ref):
    """({tier: test paths}, {changed file: why}) for the files changed since ``ref``."""
    covers = load_covers(repo)
    picked, why = {}, {}
    for path in changed_files(repo, ref):
        tier = tier_of(path)
        if tier is not None:
            targets = [path] if path in tier_files(repo, tier) else tier_files(repo, tier)
            why[path] = "a test" if targets == [path] else f"a helper of the {tier} tier"
        else:
            key = cover_key(covers, path)
            if key is None:
                why[path] = "covered by no key of test/covers.yaml: the whole suite"
                return {t: tier_files(repo, t) for t in TIERS}, why
            targets = [p for target in covers[key] for p in expand(repo, target)]
            if path.startswith(PACKAGE + "/") and path.endswith(".py"):
                targets += importers(repo, path)
            why[path] = f"covers.yaml key {key}"
        for target in targets:
            picked.setdefault(tier_of(target), set()).add(target)
    return {tier: sorted(paths) for tier, paths in picked.items()}, why
