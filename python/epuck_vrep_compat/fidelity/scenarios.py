"""The e-puck paper's section 4.1 scenarios, one table, and a robot's topics in a bag.

Each scenario: its world file, the forward speed commanded [m/s] for how long [s of simulated
time], and the topics that ``fit_noise`` needs from a bag of it. Topic names of both profiles
and of V-REP's model (the ``vrep`` profile's names) are recognised.
"""
import re
from dataclasses import dataclass
from typing import Optional, Tuple


@dataclass(frozen=True)
class Scenario:
    """One experiment of section 4.1."""

    name: str
    world: str                    # file name under worlds/
    speed_m_s: float              # commanded forward speed (negative: reversing)
    drive_s: float                # how long it is commanded, simulated seconds
    duration_s: float             # length of a recording of it
    ir_sensors: Tuple[int, ...]   # proximity sensors the scenario needs
    needs_imu: bool

    def speed_at(self, t_s: float) -> float:
        """The commanded speed ``t_s`` simulated seconds after the start."""
        return self.speed_m_s if 0.0 <= t_s < self.drive_s else 0.0


SCENARIOS = {
    # open space, standing: every IR reading below max range is an error (61/380 on sensor 0)
    "rest": Scenario("rest", "paper_rest.yaml", 0.0, 0.0, 20.0, tuple(range(8)), True),
    # Table 1: straight at 4 cm/s in open space
    "straight": Scenario("straight", "paper_straight.yaml", 0.04, 20.0, 20.0,
                         tuple(range(8)), True),
    # Fig. 4: a wall 0.5 cm ahead, reversing 3 s at 2.5 cm/s (out of the 5 cm range), then still
    "wall": Scenario("wall", "paper_wall.yaml", -0.025, 3.0, 8.0, (0, 1, 6, 7), False),
}

# a robot's topics: /<namespace>/proximity<k>, /<namespace>/imu; the namespace may be nested
# (team_a/epuck_1) or the root (a single robot, names:=/ or the drivers' own launch files)
_IR = re.compile(r"^(?P<ns>(/[^/]+)*)/proximity(?P<k>[0-7])$")
_IMU = re.compile(r"^(?P<ns>(/[^/]+)*)/(imu|accel)$")
ROOT = "/"          # the name of a robot at the root namespace


def robot_name(namespace: str) -> str:
    """The robot's name as the launch files' ``names`` spell it: ``ePuck0``, ``team_a/epuck_1``,
    ``/`` for the root namespace (a leading or trailing slash is ignored; empty is the root)."""
    name = namespace.strip("/")
    return name if name else ROOT


def topic_prefix(robot: str) -> str:
    """The robot's topics' prefix: ``/ePuck0/``, ``/`` for the root namespace."""
    name = robot_name(robot)
    return "/" if name == ROOT else f"/{name}/"


@dataclass
class RobotTopics:
    """A robot's topics as found in a bag (None where the bag has none)."""

    robot: str
    ir: dict                      # sensor index -> topic
    imu: Optional[str]
    cmd_vel: Optional[str]

    def missing(self, scenario: Scenario):
        """The topics the scenario needs that the bag lacks (names as the profile spells them)."""
        prefix = topic_prefix(self.robot)
        lost = [f"{prefix}proximity{k}" for k in scenario.ir_sensors if k not in self.ir]
        if scenario.needs_imu and self.imu is None:
            lost.append(f"{prefix}imu (or {prefix}accel)")
        return lost


def robots_in(topics) -> list:
    """Names of the robots with a proximity or IMU topic, sorted."""
    found = set()
    for t in topics:
        m = _IR.match(t) or _IMU.match(t)
        if m:
            found.add(robot_name(m.group("ns")))
    return sorted(found)


def robot_topics(topics, robot: str) -> RobotTopics:
    """The topics of ``robot`` among ``topics`` (a bag's topic names)."""
    topics = set(topics)
    robot = robot_name(robot)
    prefix = topic_prefix(robot)
    ir = {int(m.group("k")): t for t in topics
          for m in [_IR.match(t)] if m and robot_name(m.group("ns")) == robot}
    imu = next((t for t in (f"{prefix}imu", f"{prefix}accel") if t in topics), None)
    cmd = next((t for t in (f"{prefix}cmd_vel", f"{prefix}mobile_base/cmd_vel")
                if t in topics), None)
    return RobotTopics(robot, ir, imu, cmd)
