"""The C++ core's rooms include one way (see ARCHITECTURE.md's core row).

The order is written once, in CMakeLists.txt: each ``evc_core_room(<room> ... LINKS ...)``
names the rooms its library links, and a room may use those and what they link. This test
reads the includes of every core file (``include/epuck_vrep_compat/<room>/``,
``src/core/<room>/``, ``test/core_cpp/<room>/``) and of the bindings, and fails on a file
outside a room, an include of a room its own does not link, a circle among the rooms, and a
private header (``src/core/<room>/``) included by a public header, a test or a binding.
"""
import os
import re

import pytest

from repo import REPO

TREES = {"public": os.path.join("include", "epuck_vrep_compat"),
         "private": os.path.join("src", "core"),
         "test": os.path.join("test", "core_cpp")}
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)


def room_links():
    """{room: the rooms its library links directly}, from CMakeLists.txt."""
    text = open(os.path.join(REPO, "CMakeLists.txt"), encoding="utf-8").read()
    links = {}
    for room, arguments in re.findall(r"^evc_core_room\((\w+)([^)]*)\)", text, re.M):
        after = arguments.split("LINKS", 1)[1] if "LINKS" in arguments else ""
        links[room] = set(re.findall(r"epuck_vrep_compat_(\w+)", after))
    return links


def reachable(links, room):
    """The rooms @p room links, directly or through others (itself only through a circle)."""
    seen, todo = set(), list(links.get(room, ()))
    while todo:
        other = todo.pop()
        if other not in seen:
            seen.add(other)
            todo.extend(links.get(other, ()))
    return seen


def place(kind, rel):
    """(kind, room, rel): the room is None for a file that is not directly in a room's folder."""
    parts = os.path.relpath(rel, TREES[kind]).split(os.sep)
    return kind, (parts[0] if len(parts) == 2 else None), rel


def core_files():
    """place() of every file of the three trees, paths relative to REPO."""
    for kind, tree in TREES.items():
        for folder, _dirs, files in os.walk(os.path.join(REPO, tree)):
            for name in sorted(files):
                yield place(kind, os.path.relpath(os.path.join(folder, name), REPO))


def problems(links, files, read):
    """What breaks the rooms' order among @p files, each read by ``read(rel)``."""
    found = []
    for kind, room, rel in files:
        if room not in links:
            found.append(f"{rel}: not in a room's folder ({', '.join(sorted(links))})")
            continue
        allowed = reachable(links, room) | {room}
        for header in INCLUDE.findall(read(rel)):
            parts = header.split("/")
            if parts[0] == "epuck_vrep_compat" and len(parts) == 3:
                there, private = parts[1], False
            elif len(parts) == 2:
                there, private = parts[0], True
            elif os.path.exists(os.path.join(REPO, os.path.dirname(rel), header)):
                there, private = room, kind == "private"
            else:
                found.append(f"{rel}: includes {header}, which is in no room")
                continue
            if there not in allowed:
                found.append(f"{rel} ({room}) includes {header} ({there}): not linked")
            if private and kind != "private":
                found.append(f"{rel} ({kind}) includes the private header {header}")
    return found


def read_repo(rel):
    return open(os.path.join(REPO, rel), encoding="utf-8").read()


def test_the_rooms_have_no_circle():
    links = room_links()
    assert {"random", "world", "epuck", "sensors", "render", "transport"} <= set(links)
    assert [room for room in links if room in reachable(links, room)] == []
    assert links["transport"] == set()   # the writer stands alone: no Bullet, no other room


def test_every_core_file_includes_only_rooms_its_room_links():
    assert problems(room_links(), list(core_files()), read_repo) == []


def test_the_bindings_include_only_public_headers():
    folder = os.path.join(REPO, "src", "bindings")
    wrong = [f"{name}: {header}" for name in sorted(os.listdir(folder))
             for header in INCLUDE.findall(read_repo(os.path.join("src", "bindings", name)))
             if not header.startswith("epuck_vrep_compat/") and header != "binding_helpers.hpp"]
    assert wrong == []


@pytest.mark.parametrize("kind, rel, source, expected", [
    ("private", "src/core/sensors/x.cpp", '#include "epuck_vrep_compat/render/ray_camera.hpp"\n',
     "(sensors) includes epuck_vrep_compat/render/ray_camera.hpp (render): not linked"),
    ("private", "src/core/world/x.cpp", '#include "random/ziggurat.hpp"\n', "(random): not linked"),
    ("public", "include/epuck_vrep_compat/epuck/x.hpp", '#include "world/body.hpp"\n',
     "(public) includes the private header world/body.hpp"),
    ("test", "test/core_cpp/x_test.cpp", "", "x_test.cpp: not in a room's folder"),
])
def test_the_check_finds_each_problem(kind, rel, source, expected):
    found = problems(room_links(), [place(kind, rel)], lambda _rel: source)
    assert len(found) == 1 and expected in found[0], found
