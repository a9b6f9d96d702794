"""Launch files for the runs: finding the user's, reading their arguments, writing each run's.

A run is one roslaunch of one generated file that includes the simulator's launch file and the
user's launch files unchanged, starts the user's nodes as ``rosrun`` would, sets the varied ROS
parameters, and starts the ``experiment_probe`` node (required: its end is the run's end).
"""
import fnmatch
import json
import os
import shlex
import xml.etree.ElementTree as ET
from xml.sax.saxutils import escape, quoteattr

import rospkg
import yaml

PROBE = ("epuck_vrep_compat", "experiment_probe")
BAG_NODE = "/experiment_bag"     # rosbag record of a run with a bag (``bag_dir``)
# several runs per launch: the user's nodes come back this long after they end [s of wall
# time], time for every other node of the launch to have ended first (probe_walks)
RESPAWN_DELAY_S = 1.0
RESPAWN_ARG = "respawn_nodes"    # a launch file's argument: its nodes (not a simulator) respawn


def package_path(folders, env=None):
    """ROS_PACKAGE_PATH with ``folders`` first (and not twice)."""
    old = (env if env is not None else os.environ).get("ROS_PACKAGE_PATH", "")
    parts = list(folders) + [p for p in old.split(os.pathsep) if p and p not in folders]
    return os.pathsep.join(parts)


def resolve(value, base_dir):
    """The absolute path of a launch file given as a path (absolute or relative to
    ``base_dir``) or as ``PACKAGE/path/in/package`` (also ``PACKAGE/x.launch`` for the
    package's ``launch/`` folder); None when there is no such file."""
    candidates = [value if os.path.isabs(value) else os.path.join(base_dir, value)]
    package, _, rest = value.partition("/")
    if rest and not os.path.isabs(value):
        try:
            root = rospkg.RosPack().get_path(package)
            candidates += [os.path.join(root, rest), os.path.join(root, "launch", rest)]
        except rospkg.ResourceNotFound:
            pass
    return next((os.path.abspath(c) for c in candidates if os.path.isfile(c)), None)


def declared_args(path):
    """The names of the ``<arg>`` elements of a launch file (its top level and its groups) that
    an includer may set, or None when it cannot be read (the run will say why). Not the
    ``<arg>`` given to an ``<include>`` (those set another file's), nor one with a ``value``
    (a constant: roslaunch refuses to override it)."""
    try:
        root = ET.parse(path).getroot()
    except (OSError, ET.ParseError):
        return None
    names, scopes = set(), [root]
    while scopes:
        for element in scopes.pop():
            if element.tag == "group":
                scopes.append(element)
            elif element.tag == "arg" and element.get("name") and element.get("value") is None:
                names.add(element.get("name"))
    return names


def find_node(package, node_type):
    """The executable ``node_type`` of ``package`` as rosrun finds it, or None."""
    try:
        root = rospkg.RosPack().get_path(package)
    except rospkg.ResourceNotFound:
        return None
    for folder, dirs, files in os.walk(root, followlinks=True):
        dirs[:] = [d for d in dirs if not d.startswith(".")]
        if node_type in files:
            path = os.path.join(folder, node_type)
            if os.access(path, os.X_OK):
                return path
    # catkin's devel space keeps installed scripts out of the source folder
    from catkin.find_in_workspaces import find_in_workspaces   # Debian's catkin package
    found = find_in_workspaces(["libexec"], project=package, first_matching_workspace_only=False)
    for folder in found:
        path = os.path.join(folder, node_type)
        if os.access(path, os.X_OK):
            return path
    return None


def cmd_vel_lockstep(pace, declared):
    """The simulator's arguments for the e-puck half of lock-step: with a lock-step ``pace``
    whose ``wait_for`` names robots' ``cmd_vel`` topics (or patterns), a simulator launch file
    that declares ``lockstep_cmd_vel`` and ``lockstep_timeout`` (``epucks.launch``) is told to
    wait after each step for those commands, so that the step the probe triggers uses the
    command that answered the last one (the probe sees it on its own connection, which may be
    ahead of the simulator's). The simulator's timeout is half the probe's step timeout: a dead
    node's step is late for the simulator before it is for the probe. {} otherwise."""
    topics = [t for t in pace.get("wait_for", []) if t.rsplit("/", 1)[-1] == "cmd_vel"]
    timeout_s = 0.5 * float(pace.get("step_timeout_s", 1.0))
    if (pace.get("mode") != "lockstep" or not topics or timeout_s <= 0.0
            or not {"lockstep_cmd_vel", "lockstep_timeout"} <= set(declared)):
        return {}
    return {"lockstep_cmd_vel": json.dumps(topics), "lockstep_timeout": timeout_s}


def _value(v):
    if isinstance(v, bool):
        return "true" if v else "false"
    return str(v)


def _arg(name, value):
    return f'    <arg name={quoteattr(name)} value={quoteattr(_value(value))}/>'


def run_launch(run):
    """The XML of one run's launch file. ``run`` is a ``plan.RunTask``; with ``run.walks``
    (several runs in one launch), the user's nodes respawn (``RESPAWN_DELAY_S`` after they end)
    and launch files that declare a ``respawn_nodes`` argument are given it true, so that
    the probe can start them again for each run (``probe_walks``)."""
    out = ["<launch>", '  <param name="/use_sim_time" value="true"/>',
           f'  <param name="/experiment/seed" value="{run.seed}"/>',
           f'  <param name="/experiment/run_key" value="{run.key}"/>']
    for name, value in sorted(run.global_params.items()):
        out.append(f"  <rosparam param={quoteattr(name)}>{_yaml(value)}</rosparam>")
    respawn = bool(run.walks)
    out += _include(run.sim_launch, run.sim_args, respawn)
    for entry in run.code:
        if entry["kind"] == "launch":
            out += _include(entry["launch"], entry["args"], respawn)
        else:
            out += _node(entry, respawn)
    out += _probe(run)
    if run.bag_dir:
        out += _bag(run)
    out.append("</launch>")
    return "\n".join(out) + "\n"


def _yaml(value):
    """``value`` as YAML, escaped for the text of an XML element (a string may hold & or <)."""
    text = yaml.safe_dump(value, default_flow_style=True).strip()
    return escape(text[:-4] if text.endswith("\n...") else text.replace("\n...", ""))


def _include(path, args, respawn):
    """An ``<include>`` of ``path`` with ``args`` (and ``respawn_nodes:=true`` when asked and
    declared)."""
    if respawn and RESPAWN_ARG in (declared_args(path) or ()):
        args = {**args, RESPAWN_ARG: True}
    return ([f"  <include file={quoteattr(path)}>"]
            + [_arg(k, v) for k, v in sorted(args.items())] + ["  </include>"])


def _node(entry, respawn=False):
    attrs = (f'pkg={quoteattr(entry["package"])} type={quoteattr(entry["type"])} '
             f'name={quoteattr(entry["name"])} ns={quoteattr(entry["namespace"])} '
             f'args={quoteattr(entry["args"])} output="log"')
    if respawn:
        attrs += f' respawn="true" respawn_delay="{RESPAWN_DELAY_S:g}"'
    out = [f"  <node {attrs}>"]
    for name, value in sorted(entry["params"].items()):
        out.append(f"    <rosparam param={quoteattr(name)}>{_yaml(value)}</rosparam>")
    for src, dst in sorted(entry["remap"].items()):
        out.append(f"    <remap from={quoteattr(src)} to={quoteattr(str(dst))}/>")
    out.append("  </node>")
    return out


def _literal_topics(run):
    """The recorded topics when every pattern names one topic (no glob), else None."""
    return None if any(c in p for p in run.record for c in "*?[") else list(run.record)


def _bag(run):
    """rosbag record of the recorded topics into the run's folder (copied out by the runner):
    by name when every pattern names one topic, so that it subscribes as it starts; else by a
    regular expression, whose topics rosbag looks for once a second of ROS time, which the
    paused simulation does not advance: it joins a step or a few after the start."""
    bag = os.path.join(os.path.dirname(run.recording_path), "run.bag")
    topics = _literal_topics(run)
    if topics is None:
        topics = ["-e", "|".join(fnmatch.translate(p).replace("\\Z", "$").replace("(?s:", "(?:")
                                 for p in run.record)]
    args = " ".join(shlex.quote(a) for a in ["-O", bag] + topics)
    return [f'  <node pkg="rosbag" type="record" name="{BAG_NODE[1:]}" output="log" '
            f'args={quoteattr(args)}/>']


def _probe(run):
    settings = {"duration_s": run.duration_s, "out": run.recording_path,
                "topics": run.record, "pace": run.pace}
    if run.walks:
        settings["walks"] = run.walks
    if run.bag_dir and _literal_topics(run) is not None:
        settings["recorder"] = BAG_NODE         # the probe waits for the bag's subscriptions
    return [f'  <node pkg="{PROBE[0]}" type="{PROBE[1]}" name="experiment_probe" '
            'required="true" output="log">',
            f"    <rosparam>{_yaml(settings)}</rosparam>", "  </node>"]
