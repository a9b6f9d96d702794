"""The walking operator: a primitive human (cylinder body, sphere head) moved by his motion (a
polyline walked out and back, a seeded random walk, or a recorded trace: :mod:`.operator_motion`)
as a function of the time since the simulation started or was reset. Kinematic: he goes through
robots rather than around them, as V-REP's path-following "Bill" does."""
import numpy as np

from epuck_vrep_compat._core import GROUP_DYNAMIC
from epuck_vrep_compat.cell.devices.operator_motion import PingPongPath, trace_path
from epuck_vrep_compat.cell.devices.operator_walk import Floor, generate_walk
from epuck_vrep_compat.compat import vrep_codes as vc
from epuck_vrep_compat.geometry.transforms import IDENTITY_QUAT, quat_from_yaw
from epuck_vrep_compat.scene.operator_file import override_motion


def operator_motion(spec, arena_size_m, robots):
    """The motion of ``spec`` (an OperatorSpec, its trace on the floor: the scene checked it)
    in an arena of ``arena_size_m`` (centred on the origin) with ``robots`` ((name, base x,
    base y) each): (path, the legs of a walk or None)."""
    if spec.walk is not None:
        return generate_walk(spec.walk, Floor.of_arena(arena_size_m, spec.body_radius_m), robots)
    if spec.trace is not None:
        return trace_path(spec.trace), None
    return PingPongPath(spec.waypoints_m, spec.speed_m_s), None


class WalkingOperator:
    """Where the operator is at the time :meth:`seek` last set (0 at the start)."""

    def __init__(self, spec, path, legs=None, arena_size_m=None, robots=()):
        self.spec = spec
        self.path = path                 # PingPongPath or TimedPath: .at(t), .duration_s
        self.legs = legs                 # a generated walk's legs, else None
        self.time_s = 0.0                # since the start or the last reset
        self._floor = (arena_size_m, list(robots))     # what a new walk is generated on

    def rewalk(self, walk_seed: int):
        """From now on the walk of ``walk_seed`` (the scene's walk under that seed, as
        ``~operator_walk_seed`` gives at build: :func:`override_motion`)."""
        spec = override_motion(self.spec, walk_seed=walk_seed)
        self.path, self.legs = operator_motion(spec, *self._floor)
        self.spec = spec

    def seek(self, time_s: float):
        self.time_s = float(time_s)

    def reset(self):
        self.time_s = 0.0

    def describe(self) -> str:
        """His motion in a line, for the log."""
        s = self.spec
        if s.walk is not None:
            robots = sorted({leg.approaches for leg in self.legs if leg.approaches})
            return (f"{s.name} walks seed {s.walk.seed}: {len(self.legs)} legs in "
                    f"{self.path.duration_s:.2f} s, approaching {', '.join(robots) or 'no robot'}")
        if s.trace is not None:
            return (f"{s.name} replays '{s.trace.path}': {len(s.trace.t_s)} rows, "
                    f"{self.path.duration_s:.2f} s")
        return f"{s.name} walks {len(s.waypoints_m)} waypoints at {s.speed_m_s} m/s, out and back"

    def state(self):
        """(x, y, heading [rad], moving or outbound?) at the current time."""
        return self.path.at(self.time_s)

    def pose(self):
        """Base frame on the floor under the body's axis, x = walking direction."""
        x, y, heading, _ = self.state()
        return np.array([x, y, 0.0]), quat_from_yaw(heading)

    @property
    def body_centre_z(self) -> float:
        return 0.5 * self.spec.body_height_m

    @property
    def head_centre_z(self) -> float:
        return self.spec.body_height_m + self.spec.head_radius_m

    @property
    def height(self) -> float:
        return self.spec.body_height_m + 2.0 * self.spec.head_radius_m


def add_operator(spec, registry, world, arena_size_m, robots):
    """The operator of ``spec`` (an OperatorSpec) into the scene: its body (a cylinder whose
    pose follows his motion, :func:`operator_motion`) and head (a sphere on it), in the registry
    and the collision world. Returns (the WalkingOperator, (body handle, head handle))."""
    operator = WalkingOperator(spec, *operator_motion(spec, arena_size_m, robots),
                               arena_size_m=arena_size_m, robots=robots)
    base = registry.add(spec.name, vc.OBJECT_SHAPE, vc.WORLD, pose_source=operator.pose,
                        properties=dict(shape="cylinder", color=spec.color))
    world.add_cylinder(base.handle, spec.body_radius_m, spec.body_height_m, np.zeros(3),
                       IDENTITY_QUAT, spec.color, GROUP_DYNAMIC)
    head = registry.add(spec.name + "_head", vc.OBJECT_SHAPE, base.handle,
                        (0.0, 0.0, operator.head_centre_z),
                        properties=dict(shape="sphere", color=spec.color))
    world.add_sphere(head.handle, spec.head_radius_m, np.zeros(3), IDENTITY_QUAT, spec.color,
                     GROUP_DYNAMIC)
    return operator, (base.handle, head.handle)
