"""The package's layers import one way (see ARCHITECTURE.md, which this test keeps true).

Walks every module of ``python/epuck_vrep_compat`` with ``ast`` (imports inside functions
included, since a lazy import is an import all the same) and fails on an import from a higher
layer, an import between two groups of one layer, an import circle between modules, or a
private name (leading underscore) imported from another module. The layer order is written
once, here: LAYERS, bottom first; inside ``ros`` the same again with ROS_LAYERS. Two rules on
top: the bottom packages of names and geometry import only Python's library and numpy, and the
client packages import of the package only those, the messages and other clients.
"""
import ast
import os
import sys
from collections import defaultdict

import pytest

from repo import REPO

PACKAGE_DIR = os.path.join(REPO, "python", "epuck_vrep_compat")
PKG = "epuck_vrep_compat"

# Bottom first. A module may import from its own group and from any group of a lower layer.
LAYERS = (
    ("_core", "paths", "msg", "srv"),   # the compiled core, data paths, generated messages
    ("compat", "geometry"),             # names and codes once; pure geometry: no ROS, no core
    ("policy",),                        # observation builder, shipped controller: numpy only
    ("scene",),                         # scene and model files, registry, placement
    ("devices",),                       # the components' interface, every family's
    ("sim",),                           # the world (no robot family) and its extension interface
    ("epuck", "cell"),                  # the robot families, extensions: never import each other
    ("builder",),                       # one simulation from a scene and a config, every extension
    ("vrep",),                          # V-REP's API on the simulation, ROS-free
    ("ros", "learn"),                   # the faces: ROS (the node) and learning (no ROS)
    ("thesis", "nodes", "fidelity"),    # client nodes: they talk to the simulator through ROS
    ("experiment",),                    # many runs of clients and the simulator, on Dask
)
ROS_LAYERS = (                          # inside ros/, bottom first
    ("common",),                        # throttled log, parameter checks (shared with clients),
                                        # the faces' shared lock-step wait
    ("transport", "messages", "face"),  # the step batch and wire layouts, builders, protocol
    ("epuck", "vrep_plugin", "cell"),   # the faces: never import each other
    ("node",),                          # the simulator node that holds the faces
)
PRIVATE_MODULES_ALLOWED = {f"{PKG}._core"}   # the binding, re-exported by the package
PURE = ("compat", "geometry", "policy")  # plain Python (and numpy): every layer and client uses them
PURE_MAY_IMPORT = set(sys.stdlib_module_names) | {"numpy"}
PURE_MAY_USE = {"policy": ("policy", "compat", "geometry")}   # a pure group's pure groups below
# compiled helpers a pure group may load: not the simulator's core, no ROS (the C library's
# functions over arrays, geometry/fixed_order.py)
PURE_COMPILED = ("_libm",)
NO_ROS = ("learn",)                     # faces on the simulation that must not load ROS
ROS_MODULES = {"rospy", "rosgraph", "roslib", "rospkg", "roslaunch", "rostest", "genpy",
               "std_msgs", "sensor_msgs", "geometry_msgs", "nav_msgs", "tf2_ros", "tf",
               "rosbag", "rostopic", "visualization_msgs", "tf2_msgs", "rosgraph_msgs"}
CLIENTS = ("thesis", "nodes", "fidelity", "experiment")   # they talk to the simulator by ROS only
CLIENTS_MAY_IMPORT = PURE + ("msg", "srv") + CLIENTS       # (between clients, as LAYERS allows)
CLIENT_EXCEPTIONS = {                   # module: why a client may import it
    f"{PKG}.ros.common.log": "the one throttled log, shared with the simulator node; rospy only",
    f"{PKG}.ros.common.params": "the one ParamError and parameter validators; rospy only",
    f"{PKG}.ros.common.late_steps": "each node's steps taken without waiting, for the "
                                    "experiment's row; shared with the simulator; rospy only",
}


def module_files():
    for folder, _dirs, files in os.walk(PACKAGE_DIR):
        for name in files:
            if name.endswith(".py"):
                path = os.path.join(folder, name)
                rel = os.path.relpath(path, os.path.dirname(PACKAGE_DIR))[:-3].split(os.sep)
                if rel[-1] == "__init__":
                    rel = rel[:-1]
                yield ".".join(rel), path, name == "__init__.py"


def imports_of(module, path, is_package):
    """(imported module, imported names) for every import of ours in the file."""
    tree = ast.parse(open(path, encoding="utf-8").read(), path)
    here = module.split(".") if is_package else module.split(".")[:-1]
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name.split(".")[0] == PKG:
                    yield alias.name, ()
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = here[:len(here) - node.level + 1]
                target = ".".join(base + ([node.module] if node.module else []))
            else:
                target = node.module or ""
            if target.split(".")[0] == PKG:
                yield target, tuple(a.name for a in node.names)


def resolve(target, names, modules):
    """The modules an import loads: ``from pkg import module`` names a module."""
    found = [f"{target}.{n}" for n in names if f"{target}.{n}" in modules]
    return found or [target]


def place(module):
    """(layer, group) of a module, with ROS's inner layers as fractions."""
    parts = module.split(".")
    if len(parts) == 1:
        return None                                     # the package's __init__
    top = parts[1]
    for k, groups in enumerate(LAYERS):
        if top in groups:
            if top == "ros" and len(parts) > 2:
                for j, inner in enumerate(ROS_LAYERS):
                    if parts[2] in inner:
                        return k + (j + 1) / 10, f"ros.{parts[2]}"
                return None, f"ros.{parts[2]}"
            return k, top
    return None, top


@pytest.fixture(scope="module")
def graph():
    files = list(module_files())
    modules = {m for m, _, _ in files}
    edges, private = defaultdict(set), []
    for module, path, is_package in files:
        for target, names in imports_of(module, path, is_package):
            for name in names:
                if name.startswith("_") and f"{target}.{name}" not in PRIVATE_MODULES_ALLOWED \
                        and target != module:
                    private.append(f"{module} imports {name} from {target}")
            for loaded in resolve(target, names, modules):
                if loaded != module:
                    edges[module].add(loaded)
    return modules, edges, private


def test_every_module_has_a_layer(graph):
    modules, _, _ = graph
    unplaced = sorted(m for m in modules if place(m) is not None and place(m)[0] is None)
    assert unplaced == [], "modules outside LAYERS/ROS_LAYERS (add their folder there and to " \
                           "ARCHITECTURE.md): " + ", ".join(unplaced)


def test_no_import_from_a_higher_layer_or_sideways(graph):
    _, edges, _ = graph
    wrong = []
    for module, targets in edges.items():
        here = place(module)
        for target in targets:
            there = place(target)
            if here is None or there is None or here[0] is None or there[0] is None:
                continue
            if there[0] > here[0] or (there[0] == here[0] and there[1] != here[1]):
                wrong.append(f"{module} ({here[1]}) imports {target} ({there[1]})")
    assert wrong == [], "imports against the layer order:\n" + "\n".join(sorted(wrong))


def test_no_import_circle(graph):
    modules, edges, _ = graph
    index, low, stack, on_stack, circles, counter = {}, {}, [], set(), [], [0]

    def visit(v):                            # Tarjan's strongly connected components
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on_stack.add(v)
        for w in edges.get(v, ()):
            if w not in modules:
                continue
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                circles.append(sorted(component))
    for m in sorted(modules):
        if m not in index:
            visit(m)
    # a package's __init__ importing its own modules is how packages export: not a circle
    circles = [c for c in circles if not all(m == c[0] or m.startswith(c[0] + ".") for m in c)]
    assert circles == [], "import circles: " + "; ".join(" <-> ".join(c) for c in circles)


def test_no_private_name_imported_from_another_module(graph):
    _, _, private = graph
    assert private == [], "\n".join(sorted(private))


def outside_imports(path):
    """The top-level names of every module a file imports that is not ours."""
    tree = ast.parse(open(path, encoding="utf-8").read(), path)
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            yield from (a.name.split(".")[0] for a in node.names)
        elif isinstance(node, ast.ImportFrom) and not node.level and node.module:
            yield node.module.split(".")[0]


def pure_import_problems(module, path, is_package):
    """What a module of compat, geometry or policy imports beyond the library, numpy, its own
    group and the pure groups it may use (PURE_MAY_USE)."""
    group = module.split(".")[1]
    wrong = [f"{module} imports {name}" for name in outside_imports(path)
             if name not in PURE_MAY_IMPORT | {PKG}]
    return wrong + [f"{module} imports {target}"
                    for target, _ in imports_of(module, path, is_package)
                    if target.split(".")[1:2] == [] or
                    target.split(".")[1] not in PURE_MAY_USE.get(group, (group,)) + PURE_COMPILED]


def test_names_and_geometry_speak_no_ros():
    """compat, geometry and policy load nothing but Python's library and numpy: no ROS, no
    core, no other part of the package than the pure groups below them (so the ROS-free
    layers, and the clients, stay ROS-free and core-free through them)."""
    wrong = [problem for module, path, is_package in module_files()
             if module.split(".")[1:2] and module.split(".")[1] in PURE
             for problem in pure_import_problems(module, path, is_package)]
    assert wrong == [], "\n".join(sorted(wrong))


def ros_import_problems(module, path):
    """What a module of a ROS-free face (NO_ROS) imports of ROS, or of the package's ROS parts
    (the messages, ros/, the clients)."""
    wrong = [f"{module} imports {name}" for name in outside_imports(path) if name in ROS_MODULES]
    ros_parts = ("msg", "srv", "ros") + CLIENTS
    return wrong + [f"{module} imports {target}" for target, _ in imports_of(module, path, False)
                    if target.split(".")[1:2] and target.split(".")[1] in ros_parts]


def test_learning_environments_load_no_ros():
    """learn/ is a face on the simulation beside the ROS faces that loads nothing of ROS: the
    environments run where ROS is not installed."""
    wrong = [problem for module, path, _ in module_files()
             if module.split(".")[1:2] and module.split(".")[1] in NO_ROS
             for problem in ros_import_problems(module, path)]
    assert wrong == [], "\n".join(sorted(wrong))


def client_import_problems(edges):
    wrong = []
    for module, targets in edges.items():
        if module.split(".")[1:2] and module.split(".")[1] in CLIENTS:
            for target in targets:
                top = target.split(".")[1] if "." in target else None
                if top not in CLIENTS_MAY_IMPORT and target not in CLIENT_EXCEPTIONS:
                    wrong.append(f"{module} imports {target}")
    return wrong


def test_clients_import_only_names_geometry_messages_and_clients(graph):
    """A client (the thesis's nodes, the examples, the fidelity tools, the experiment runner)
    talks to the simulator through ROS: of the package it imports compat, geometry, the
    messages and other clients, never the simulator's layers (CLIENT_EXCEPTIONS says why)."""
    _, edges, _ = graph
    wrong = client_import_problems(edges)
    assert wrong == [], "clients importing the simulator's layers:\n" + "\n".join(sorted(wrong))


def test_the_check_sees_a_wrong_import(graph, tmp_path):
    """The walk itself works: an upward import, a circle, a private name, a client's import of
    the simulator and a ROS import in compat are found."""
    assert place(f"{PKG}.scene.registry")[0] < place(f"{PKG}.sim.simulation")[0]
    assert place(f"{PKG}.thesis.hub")[1] != place(f"{PKG}.nodes.wander")[1]
    source = tmp_path / "m.py"
    source.write_text("def f():\n    from epuck_vrep_compat.sim.simulation import _x\n")
    assert list(imports_of(f"{PKG}.scene.m", str(source), False)) == [
        (f"{PKG}.sim.simulation", ("_x",))]
    assert client_import_problems({f"{PKG}.nodes.m": {f"{PKG}.scene.registry",
                                                      f"{PKG}.compat.topics"}}) == [
        f"{PKG}.nodes.m imports {PKG}.scene.registry"]
    source.write_text("import math\nimport rospy\nfrom epuck_vrep_compat import _core\n"
                      "from epuck_vrep_compat.compat import topics\n")
    assert pure_import_problems(f"{PKG}.compat.m", str(source), False) == [
        f"{PKG}.compat.m imports rospy", f"{PKG}.compat.m imports {PKG}"]
    assert pure_import_problems(f"{PKG}.policy.m", str(source), False) == [
        f"{PKG}.policy.m imports rospy", f"{PKG}.policy.m imports {PKG}"]   # compat: allowed
    assert pure_import_problems(f"{PKG}.geometry.m", str(source), False)[-1] == \
        f"{PKG}.geometry.m imports {PKG}.compat"
    source.write_text("import rospy\nfrom sensor_msgs.msg import Range\n"
                      "from epuck_vrep_compat.ros.epuck import sensors\n")
    assert ros_import_problems(f"{PKG}.learn.m", str(source)) == [
        f"{PKG}.learn.m imports rospy", f"{PKG}.learn.m imports sensor_msgs",
        f"{PKG}.learn.m imports {PKG}.ros.epuck"]
