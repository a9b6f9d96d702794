"""The README and docs/ cannot lie about the repository: every command they show names launch
files, launch arguments, nodes, tools, files, services (with their request fields) and message
types (with their fields) that exist, and every relative link reaches its page and heading.

The commands are read by ``tools/doc_commands.py`` (fenced shell blocks and inline command
spans). Topics and services are checked against a live simulator by the rostest
``docs_walkthrough``, which also runs the README's first walk-through.
"""
import glob
import os
import re
import sys
import xml.etree.ElementTree as ET

import pytest
import rospkg
import yaml

from repo import REPO

sys.path.insert(0, os.path.join(REPO, "tools"))
import doc_commands as docs  # noqa: E402

PACKAGE_DIR = os.path.join(REPO, "python", "epuck_vrep_compat")
FIND_PKG = "$(find " + docs.PKG + ")"


# -- launch files ---------------------------------------------------------------------------

def choices(doc):
    """The values an argument's doc lists as ``a | b (why) | c; more words``, else None."""
    listed = (doc or "").split(";")[0]
    return [part.split()[0] for part in listed.split("|")] if "|" in listed else None


def launch_args(path):
    """({settable argument: (has a default, its listed values or None)}, files included with
    pass_all_args) of a launch file; an <arg> with value= is fixed, not settable."""
    root = ET.parse(path).getroot()
    settable = {a.get("name"): (a.get("default") is not None, choices(a.get("doc")))
                for a in root.iter("arg") if a.get("value") is None}
    passed = [i.get("file").replace(FIND_PKG, REPO) for i in root.iter("include")
              if i.get("pass_all_args") == "true"]
    return settable, passed


def launch_problems(launch):
    """What is wrong with ``roslaunch epuck_vrep_compat FILE a:=b ...``."""
    path = os.path.join(REPO, "launch", launch.file)
    if not os.path.exists(path):
        return [f"no launch file launch/{launch.file}"]
    settable, passed = launch_args(path)
    for included in passed:
        settable.update(launch_args(included)[0])
    known = ", ".join(sorted(settable))
    problems = [f"{launch.file} has no argument '{a}' to set (it has: {known})"
                for a in launch.args if a not in settable]
    problems += [f"{launch.file}: {a} is one of {settable[a][1]}, not '{value}'"
                 for a, value in launch.args.items()
                 if a in settable and settable[a][1] and value not in settable[a][1]]
    problems += [f"{launch.file} needs '{a}:=...'" for a, (has_default, _) in settable.items()
                 if not has_default and a not in launch.args]
    return problems


# -- services and messages ------------------------------------------------------------------

def request_fields(srv_path):
    """The request fields of a .srv file, in order."""
    text = open(srv_path, encoding="utf-8").read().split("---")[0]
    fields = []
    for line in text.split("\n"):
        line = line.split("#")[0].strip()
        if line and "=" not in line:
            fields.append(line.split()[1])
    return fields


def srv_file(module_source, type_name):
    """The .srv file of a service type a module imports (``from PKG.srv import TYPE``)."""
    match = re.search(r"from (\w+)\.srv import [^\n]*\b" + type_name + r"\b", module_source)
    if not match:
        return None
    package = match.group(1)
    base = REPO if package == docs.PKG else rospkg.RosPack().get_path(package)
    return os.path.join(base, "srv", type_name + ".srv")


def declared_services():
    """{service name: .srv file} of every service the repository offers: V-REP's ``simRos*``
    (vrep_common/srv) and those the package's modules declare with ``rospy.Service``
    (``~x`` of the simulator's faces is /vrep/x, of a client node's module /<module>/x)."""
    from epuck_vrep_compat.compat import topics as names
    services = {"/vrep/" + os.path.basename(p)[:-4]: p
                for p in glob.glob(os.path.join(REPO, "vrep_common", "srv", "simRos*.srv"))}
    for path in glob.glob(os.path.join(PACKAGE_DIR, "**", "*.py"), recursive=True):
        source = open(path, encoding="utf-8").read()
        for name, type_name in re.findall(r"rospy\.Service\(\s*([^,]+?)\s*,\s*(\w+)", source):
            if name.startswith('"~'):
                in_simulator = os.path.relpath(path, PACKAGE_DIR).startswith("ros" + os.sep)
                owner = "vrep" if in_simulator else os.path.basename(path)[:-3]
                name = f"/{owner}/{name[2:-1]}"
            else:
                name = getattr(names, name)
            services[name] = srv_file(source, type_name)
    return services


SERVICES = None


def service_problems(name):
    """What is wrong with ``rosservice call /x ARGS``: an unknown service or request field."""
    global SERVICES
    SERVICES = SERVICES or declared_services()
    srv = SERVICES.get(name.name)
    if srv is None:
        return [f"no service {name.name} in vrep_common/srv or the package's rospy.Service"]
    if not os.path.exists(srv):
        return [f"{name.name}: no {srv}"]
    fields = request_fields(srv)
    if len(name.values) == 1 and isinstance(yaml.safe_load(name.values[0]), dict):
        return [f"{name.name} has no request field '{k}' (it has: {fields})"
                for k in yaml.safe_load(name.values[0]) if k not in fields]
    if len(name.values) > len(fields):
        return [f"{name.name} takes {len(fields)} request fields, not {len(name.values)}"]
    return []


def message_problems(msg_type, values, where="message"):
    """What is wrong with the fields of a message written as YAML (``rostopic pub``)."""
    import roslib.message
    msg_class = roslib.message.get_message_class(msg_type)
    if msg_class is None:
        return [f"no message type {msg_type}"]
    if not isinstance(values, dict):
        return []
    slots = dict(zip(msg_class.__slots__, msg_class._slot_types))
    problems = []
    for key, value in values.items():
        if key not in slots:
            problems.append(f"{msg_type} has no field '{key}' ({where})")
        elif isinstance(value, dict):
            problems += message_problems(slots[key], value, f"{where}.{key}")
    return problems


def topic_problems(name):
    if name.msg_type is None:
        return []
    text = next((v for v in name.values if not v.startswith("-")), "{}")
    return message_problems(name.msg_type, yaml.safe_load(text))


# -- every command --------------------------------------------------------------------------

def command_problems(command):
    """Everything a command names that the repository does not have."""
    if not command.words:
        return ["no shell command (unbalanced quotes?)"]
    problems = []
    launch = docs.launch_of(command)
    if launch:
        problems += launch_problems(launch)
    node = docs.node_of(command)
    if node and "<" not in node:
        path = os.path.join(REPO, "scripts", node)
        if not os.access(path, os.X_OK):
            problems.append(f"no executable node scripts/{node}")
    tool = docs.tool_of(command)
    if tool and not os.path.exists(os.path.join(REPO, tool)):
        problems.append(f"no {tool}")
    problems += [f"no file {f}" for f in docs.repo_files_of(command)
                 if not os.path.exists(os.path.join(REPO, f))]
    for name in docs.names_of(command):
        problems += service_problems(name) if name.kind == "service" else topic_problems(name)
    return problems


COMMANDS = docs.all_commands(REPO)


def test_the_docs_show_commands():
    pages = {c.page for c in COMMANDS}
    assert "README.md" in pages and len(pages) >= 8, pages
    assert sum(1 for c in COMMANDS if docs.launch_of(c)) >= 10


@pytest.mark.parametrize("command", COMMANDS, ids=[f"{c.page}:{c.line}" for c in COMMANDS])
def test_every_command_names_what_exists(command):
    assert command_problems(command) == [], command.where()


LINKS = docs.links(REPO)


@pytest.mark.parametrize("page, line, target", LINKS, ids=[f"{p}:{n}" for p, n, _ in LINKS])
def test_every_link_reaches_its_page_and_heading(page, line, target):
    path, _, anchor = target.partition("#")
    full = os.path.normpath(os.path.join(REPO, os.path.dirname(page), path)) if path else \
        os.path.join(REPO, page)
    assert os.path.exists(full), f"{page}:{line}: no {path}"
    if anchor:
        assert anchor in docs.anchors(full), f"{page}:{line}: no heading #{anchor} in {path}"


def test_the_parameters_page_lists_every_argument_of_epucks_launch():
    """Its table's first column names exactly the arguments a user can set."""
    text = open(os.path.join(REPO, "docs", "parameters.md"), encoding="utf-8").read()
    table = text.split("## Launch arguments of `epucks.launch`")[1].split("\n## ")[0]
    listed = {name for row in table.split("\n") if row.startswith("| `")
              for name in re.findall(r"`(\w+)`", row.split("|")[1])}
    settable, _ = launch_args(os.path.join(REPO, "launch", "epucks.launch"))
    assert listed == set(settable)


def test_the_walkthrough_is_what_its_rostest_starts():
    """The rostest docs_walkthrough starts the simulator exactly as the walk-through does."""
    launch, lines = docs.walkthrough(REPO)
    assert lines, "the walk-through runs no command after starting the simulator"
    test_file = os.path.join(REPO, "test", "rostest", "docs_walkthrough.test")
    include = ET.parse(test_file).getroot().find("include")
    assert os.path.basename(include.get("file")) == launch.file
    assert {a.get("name"): a.get("value") for a in include.iter("arg")} == launch.args


def test_the_readme_stays_short_and_starts_with_its_two_commands():
    text = open(os.path.join(REPO, "README.md"), encoding="utf-8").read()
    assert text.count("\n") <= 150
    first = docs.fenced_blocks(text)[0][2]
    assert [line.split("#")[0].strip() for line in first] == ["bash tools/run", "bash tools/test"]


# -- the checks find what they are for ------------------------------------------------------

@pytest.mark.parametrize("block, expected", [
    ("roslaunch epuck_vrep_compat epuckz.launch", "no launch file launch/epuckz.launch"),
    ("roslaunch epuck_vrep_compat epucks.launch cmd_vel_scale:=si", "no argument 'cmd_vel_scale'"),
    ("roslaunch epuck_vrep_compat paper_wall.launch robot:=x", "no argument 'robot'"),
    ("roslaunch epuck_vrep_compat epucks.launch profile:=epuck_drivr",
     "profile is one of ['vrep', 'epuck_driver', 'epuck2_driver'], not 'epuck_drivr'"),
    ("rosrun epuck_vrep_compat fit_noisy a.bag", "no executable node scripts/fit_noisy"),
    ("bash tools/tests", "no tools/tests"),
    ("rosrun rviz rviz -d $(rospack find epuck_vrep_compat)/config/epuck.rviz",
     "no file config/epuck.rviz"),
    ("rosservice call /vrep/simRosGetObjectHandel", "no service /vrep/simRosGetObjectHandel"),
    ('rosservice call /vrep/step "stepz: 10"', "has no request field 'stepz'"),
    ("rosservice call /ssm_supervisor/set_enable false", "no service /ssm_supervisor/set_enable"),
    ("rostopic pub -1 /ePuck0/cmd_vel geometry_msgs/Twist '{linear: {q: 1}}'",
     "geometry_msgs/Vector3 has no field 'q'"),
    ("rostopic pub /a geometry_msgs/Twister '{}'", "no message type geometry_msgs/Twister"),
    ("rostopic pub /a geometry_msgs/Twist '{linear: {x: 1}}", "unbalanced quotes"),
])
def test_the_check_finds_each_wrong_name(tmp_path, block, expected):
    (tmp_path / "README.md").write_text(f"# x\n\n```bash\n{block}   # a comment\n```\n")
    commands = docs.all_commands(str(tmp_path))
    problems = [p for c in commands for p in command_problems(c)]
    assert len(problems) == 1 and expected in problems[0], problems


def test_the_check_finds_a_broken_link_and_heading(tmp_path):
    (tmp_path / "docs").mkdir()
    (tmp_path / "README.md").write_text("[a](docs/a.md#no-such) [b](docs/b.md) `bash tools/x`\n")
    (tmp_path / "docs" / "a.md").write_text("# A title\n")
    links = docs.links(str(tmp_path))
    assert [t for _, _, t in links] == ["docs/a.md#no-such", "docs/b.md"]
    assert "no-such" not in docs.anchors(str(tmp_path / "docs" / "a.md"))
    assert "a-title" in docs.anchors(str(tmp_path / "docs" / "a.md"))
    assert [c.words for c in docs.all_commands(str(tmp_path))] == [["bash", "tools/x"]]


def test_a_launch_includes_what_it_names():
    assert docs.includes("paper_wall.launch") == ["paper_wall.launch", "epucks.launch"]
    assert "thesis_nodes.launch" in docs.includes("merlin_safety.launch")
