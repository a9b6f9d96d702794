"""Private parameters of the simulator node: read once, validated, summarised in one line.

An unusable value raises :class:`ParamError` (the package's one, from ``ros/common/params.py``)
naming the parameter; the node then exits non-zero.
"""
import math
import os
from dataclasses import dataclass, field
from typing import Optional

import rospy

from epuck_vrep_compat.devices.components import CameraSpec
from epuck_vrep_compat.ros.common.params import ParamError, read_typed as _get
from epuck_vrep_compat.ros.epuck.commands import SCALINGS
from epuck_vrep_compat.ros.epuck.profiles import PROFILES
from epuck_vrep_compat.ros.epuck.robot_names import parse_robot_names, unconventional_names
from epuck_vrep_compat.ros.node.extras_params import read_extras_settings
from epuck_vrep_compat.epuck.epuck2_sensors import Epuck2Settings
from epuck_vrep_compat.epuck.noise import (
    IrNoise, NoiseConfigError, NoiseSettings, per_sensor, triple)
from epuck_vrep_compat.epuck.noise_presets import IMU_KEYS, load_noise_file, preset
from epuck_vrep_compat.scene.operator_file import check_on_floor, override_motion
from epuck_vrep_compat.scene.validation import SceneError
from epuck_vrep_compat.sim.simulation import SEED, STEP_S


@dataclass
class SimParams:
    """The simulator node's private parameters, as :func:`read_params` read them."""

    world: str = ""
    n: int = 1
    robot_names: list = field(default_factory=list)   # one per robot (a namespace, or "/")
    profile: str = "vrep"
    seed: int = SEED
    rtf: float = 1.0
    vrep_realtime: bool = False         # V-REP's real-time switch (state bit 2); V-REP's default
    speed_scale_timeout_s: float = 0.0  # the cell's speed-scale watchdog; 0 = off
    speed_scale_robots: list = field(default_factory=list)     # the watched; [] = every robot
    model_dirs: list = field(default_factory=list)  # simRosLoadModel's folders besides models/
    lockstep_timeout_s: float = 0.0     # > 0: wait for the supervisor's scales each step,
    lockstep_cmd_vel: list = field(default_factory=list)   # and for these cmd_vel topics'
    operator_walk_seed: Optional[int] = None    # the cell operator's walk, over the scene's
    operator_trace: Optional[str] = None        # his recorded trace (CSV), over the scene's
    step_s: float = STEP_S
    paused: bool = False
    cmd_vel_scaling: str = "vrep"       # the profile's own (profiles.TopicProfile defaults)
    cmd_timeout_s: float = 0.0
    accel_sign: str = "ros"
    publish_ground_truth: bool = True
    camera: CameraSpec = field(default_factory=CameraSpec)
    camera_mode: str = "rgb"                  # "rgb" (rgb8) or "gray" (mono8)
    noise: NoiseSettings = field(default_factory=NoiseSettings)
    noise_source: str = "real_robot"      # the preset, and the noise file over it if any
    extras: Epuck2Settings = field(default_factory=Epuck2Settings)   # the drivers' extras
    test_fault_hook: bool = False       # tests only: faults on command (sim/fault_hook.py)

    @property
    def cmd_vel_lockstep(self):
        """The e-puck face's lock-step: (cmd_vel topic patterns, timeout in s of wall time)."""
        return self.lockstep_cmd_vel, self.lockstep_timeout_s

    def _operator(self) -> str:
        if self.operator_walk_seed is not None:
            return f"operator_walk_seed={self.operator_walk_seed} "
        return f"operator_trace={self.operator_trace} " if self.operator_trace else ""

    def summary(self) -> str:
        return (f"world={self.world} n={self.n} robots={','.join(self.robot_names[:4])}"
                f"{'..' if self.n > 4 else ''} profile={self.profile} seed={self.seed} "
                f"noise={'on' if self.noise.enabled else 'off'} ({self.noise_source}) "
                f"rtf={self.rtf} lockstep_timeout_s={self.lockstep_timeout_s} "
                f"lockstep_cmd_vel={self.lockstep_cmd_vel} "
                f"{self._operator()}"
                f"step_s={self.step_s} paused={self.paused} cmd_vel_scaling={self.cmd_vel_scaling}"
                f" cmd_timeout_s={self.cmd_timeout_s} accel_sign={self.accel_sign} camera="
                f"{self.camera.width}x{self.camera.height}@{self.camera.rate_hz}Hz")


def read_params(default_world: str) -> SimParams:
    p = SimParams()
    p.world = _get("world", default_world, str, lambda v: v != "", "must name a scene file")
    p.n = _get("n", 1, int, lambda v: 0 <= v <= 100000, "must be between 0 and 100000")
    p.profile = _get("profile", "vrep", str, lambda v: v in PROFILES,
                     f"must be one of {sorted(PROFILES)}")
    p.robot_names = _read_robot_names(p)
    p.n = len(p.robot_names)
    p.seed = _get("seed", SEED, int, lambda v: 0 <= v < 2 ** 63, "must be a non-negative integer")
    p.rtf = _get("rtf", 1.0, float, lambda v: v >= 0.0, "must be >= 0 (0 = as fast as possible)")
    p.vrep_realtime = _get("vrep_realtime", False, bool)
    p.speed_scale_timeout_s = _get("speed_scale_timeout_s", 0.0, float,
                                   lambda v: math.isfinite(v) and v >= 0.0,
                                   "must be >= 0 s (0 = no watchdog)")
    p.speed_scale_robots = _get("speed_scale_robots", [], list,
                                lambda v: all(isinstance(r, str) and r for r in v),
                                "must be a list of cell robot names ([] = every robot)")
    p.model_dirs = _get("model_dirs", [], list,
                        lambda v: all(isinstance(d, str) and os.path.isdir(d) for d in v),
                        "must be a list of existing folders")
    p.lockstep_timeout_s = _get("lockstep_timeout_s", 0.0, float,
                                lambda v: math.isfinite(v) and v >= 0.0,
                                "must be >= 0 s of wall time (0 = no lock-step)")
    p.lockstep_cmd_vel = _get("lockstep_cmd_vel", [], list,
                              lambda v: all(isinstance(t, str) and t.startswith("/") for t in v),
                              "must be a list of absolute cmd_vel topics or patterns "
                              "(/ePuck*/cmd_vel; [] = none)")
    p.operator_walk_seed, p.operator_trace = _read_operator()
    p.step_s = _get("step_s", STEP_S, float, lambda v: 0.0 < v <= 1.0, "must be in (0, 1]")
    p.paused = _get("paused", False, bool)
    profile = PROFILES[p.profile]
    # unset or empty: the profile's original (its units; commands persist, no watchdog)
    p.cmd_vel_scaling = _get("cmd_vel_scaling", profile.default_cmd_vel_scaling, str,
                             lambda v: v in SCALINGS, f"must be one of {list(SCALINGS)}")
    p.cmd_timeout_s = _get("cmd_timeout_s", profile.default_cmd_timeout_s, float,
                           lambda v: v >= 0.0, "must be >= 0 (0 disables the watchdog)")
    p.accel_sign = _get("accel_sign", "ros", str, lambda v: v in ("ros", "vrep"),
                        "must be 'ros' (+9.81 on z at rest) or 'vrep' (-9.81)")
    p.publish_ground_truth = _get("publish_ground_truth", True, bool)
    c = p.camera
    width, height, p.camera_mode = profile.default_camera
    c.width = _get("camera/width", width, int, lambda v: 1 <= v <= 2048, "must be 1..2048")
    c.height = _get("camera/height", height, int, lambda v: 1 <= v <= 2048, "must be 1..2048")
    p.camera_mode = _get("camera/mode", p.camera_mode, str, lambda v: v in ("rgb", "gray"),
                         "must be 'rgb' (rgb8) or 'gray' (mono8, the drivers' cam_mode 0)")
    c.rate_hz = _get("camera/rate_hz", c.rate_hz, float, lambda v: v > 0.0, "must be > 0")
    fov = (slice_fov(c.vertical_fov_rad, c.height) if profile.default_camera[2] == "gray"
           else c.vertical_fov_rad)        # the drivers' window of the sensor at zoom 1
    c.vertical_fov_rad = _get("camera/vertical_fov_rad", fov, float,
                              lambda v: 0.0 < v < math.pi, "must be in (0, pi)")
    p.noise, p.noise_source = _read_noise(p.robot_names)
    p.extras = read_extras_settings(profile)
    p.test_fault_hook = _get("test_fault_hook", False, bool)
    return p


def _read_operator():
    """``~operator_walk_seed`` and ``~operator_trace``: unset or empty, the scene's operator."""
    seed = rospy.get_param("~operator_walk_seed", "")
    if seed == "":
        seed = None
    elif isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
        raise ParamError("parameter '~operator_walk_seed' must be a non-negative integer (the "
                         f"operator's walk seed) or empty (the scene's operator), got {seed!r}")
    trace = _get("operator_trace", "", str)
    if seed is not None and trace:
        raise ParamError("parameters '~operator_walk_seed' and '~operator_trace': give one, "
                         "not both")
    return seed, trace or None


def with_operator(scene, p: SimParams):
    """``scene`` with its operator moving as ``~operator_walk_seed`` or ``~operator_trace``
    say (a trace's relative path: against the scene file's folder); ParamError."""
    if p.operator_walk_seed is None and p.operator_trace is None:
        return scene
    name = "operator_walk_seed" if p.operator_trace is None else "operator_trace"
    if scene.cell is None or scene.cell.operator is None:
        raise ParamError(f"parameter '~{name}': the scene '{p.world}' has no cell operator")
    try:
        scene.cell.operator = override_motion(scene.cell.operator, p.operator_walk_seed,
                                              p.operator_trace,
                                              os.path.dirname(os.path.abspath(p.world)))
        check_on_floor(scene.cell.operator, scene.arena.size_m)
    except SceneError as e:
        raise ParamError(f"parameter '~{name}': {e}") from None
    return scene


def slice_fov(full_vertical_fov_rad: float, height: int, sensor_rows: int = 480) -> float:
    """Vertical field of view of ``height`` rows of the e-puck's 640 x 480 sensor at zoom 1
    (as the drivers' centred slices): the full image's below 480 rows, a narrow band for 2."""
    if height >= sensor_rows:
        return full_vertical_fov_rad
    return 2.0 * math.atan(math.tan(0.5 * full_vertical_fov_rad) * height / sensor_rows)


def _read_robot_names(p: SimParams) -> list:
    """``~robot_names`` (a list, or names separated by commas); unset or empty: the profile's
    ``n`` names (``ePuck0``.., ``epuck_robot_0``..)."""
    profile = PROFILES[p.profile]
    value = rospy.get_param("~robot_names", [])
    if value in ([], "", None):
        return [profile.robot_name(i) for i in range(p.n)]
    try:
        names = parse_robot_names(value, profile)
    except ValueError as e:
        raise ParamError(f"parameter '~robot_names': {e}") from e
    odd = unconventional_names(names, profile)
    if odd:
        rospy.logwarn("~robot_names: %s not named as the %s original names its robots; they work, "
                      "but a client written for the original may look for other names",
                      ", ".join(odd), profile.name)
    return names


def _read_noise(robot_names):
    """(NoiseSettings, where they come from: the preset and the noise file)."""
    try:
        source = _get("noise_preset", "real_robot", str)
        s = preset(source)
        noise_file = _get("noise_file", "", str)
        if noise_file:
            s = load_noise_file(noise_file, s)
            source += " + " + noise_file
        s.enabled = s.enabled and _get("noise", True, bool)
        s.ir = _read_ir("ir_noise/", s.ir)
        for key in IMU_KEYS:
            name = "imu_noise/" + key
            setattr(s, key, triple(rospy.get_param("~" + name, getattr(s, key).tolist()), name,
                                   None if "bias" in key else 0.0))
        robots = rospy.get_param("~robots", {})
        if not isinstance(robots, dict):
            raise ParamError("parameter '~robots' must be a mapping of robot name to overrides")
        for name in robots:
            if name not in robot_names:
                raise ParamError(f"parameter '~robots/{name}': no robot of that name "
                                 f"(robots are {', '.join(robot_names[:3])}..)")
            s.ir_per_robot[name] = _read_ir(f"robots/{name}/ir_noise/", s.ir)
    except NoiseConfigError as e:
        # the noise layer names the option; the node's private parameter is that name under ~
        raise ParamError(f"parameter '~{e.option}' {e.problem}") from e
    s.wheel_slip_stddev = _get("wheel_slip_stddev", s.wheel_slip_stddev, float,
                               lambda v: v >= 0.0, "must be >= 0")
    return s, source


def _read_ir(prefix: str, base: IrNoise) -> IrNoise:
    def value(key, default):
        return rospy.get_param("~" + prefix + key, default.tolist())
    return IrNoise(
        probability=per_sensor(value("probability", base.probability),
                               f"{prefix}probability", 0.0, 1.0),
        mean_m=per_sensor(value("mean_m", base.mean_m), f"{prefix}mean_m"),
        stddev_m=per_sensor(value("stddev_m", base.stddev_m), f"{prefix}stddev_m", 0.0))
