"""The package stays readable in one sitting (STYLE.md, ARCHITECTURE.md): no Python module over
MAX_MODULE_LINES, no function over MAX_FUNCTION_LINES, a docstring on every public class saying
what it is for. A file that needs more is a file with more than one concern: split it."""
import ast
import os

import pytest

from repo import REPO

PACKAGE_DIR = os.path.join(REPO, "python", "epuck_vrep_compat")
MAX_MODULE_LINES = 300
MAX_FUNCTION_LINES = 60


def modules():
    for folder, _dirs, files in os.walk(PACKAGE_DIR):
        for name in sorted(files):
            if name.endswith(".py"):
                path = os.path.join(folder, name)
                with open(path, encoding="utf-8") as f:
                    source = f.read()
                yield os.path.relpath(path, PACKAGE_DIR), source, ast.parse(source, path)


def shape_problems(rel, source, tree):
    problems = []
    lines = source.count("\n")
    if lines > MAX_MODULE_LINES:
        problems.append(f"{rel}: {lines} lines (at most {MAX_MODULE_LINES})")
    for node in ast.walk(tree):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            length = node.end_lineno - node.lineno + 1
            if length > MAX_FUNCTION_LINES:
                problems.append(f"{rel}:{node.lineno} {node.name}(): {length} lines "
                                f"(at most {MAX_FUNCTION_LINES})")
        elif isinstance(node, ast.ClassDef) and not node.name.startswith("_") \
                and not ast.get_docstring(node):
            problems.append(f"{rel}:{node.lineno} class {node.name} has no docstring")
    return problems


def test_modules_functions_and_classes_keep_their_shape():
    found = [p for rel, source, tree in modules() for p in shape_problems(rel, source, tree)]
    assert found == [], "\n".join(found)


@pytest.mark.parametrize("source, expected", [
    ("class Thing:\n    pass\n", "class Thing has no docstring"),
    ("def f():\n" + "    x = 1\n" * MAX_FUNCTION_LINES, "f(): 61 lines"),
    ("x = 1\n" * (MAX_MODULE_LINES + 1), "301 lines"),
])
def test_the_check_finds_each_problem(source, expected):
    problems = shape_problems("m.py", source, ast.parse(source))
    assert len(problems) == 1 and expected in problems[0], problems


def test_documented_private_and_short_pass():
    source = 'class Thing:\n    """What it is for."""\n\n\nclass _Private:\n    pass\n'
    assert shape_problems("m.py", source, ast.parse(source)) == []
