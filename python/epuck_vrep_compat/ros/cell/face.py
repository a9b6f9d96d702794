"""The cell's face: what V-REP's cell scene published through its models' scripts.

- The laser scan (:mod:`laser`), the cell's TF (:mod:`transforms`), each robot's joint topics
  (:mod:`joints`) and what rviz needs (:mod:`rviz`).
- The safety interface (:mod:`safety`): each robot's speed scale in, the operator-to-link
  separation service.

The ceiling cameras' blob positions are not this face's: the cell writes them as float signals
each step and declares them published from the start (``Cell.published_signals``), and the
``/vrep`` face enables their streams (``/vrep/Blob_Camera_0_X`` ...).
"""
from epuck_vrep_compat.ros.cell.joints import ArmTopics
from epuck_vrep_compat.ros.cell.laser import LaserTopic
from epuck_vrep_compat.ros.cell.rviz import CellRviz
from epuck_vrep_compat.ros.cell.safety import CellSafety
from epuck_vrep_compat.ros.cell.transforms import CellTransforms
from epuck_vrep_compat.ros.common.log import ThrottledLog
from epuck_vrep_compat.ros.face import Face, Step


class CellFace(Face):
    """The industrial cell: joint states and commands, the laser scan, the cell's TF, robot
    descriptions and markers for rviz.

    Commands go to the model through the cell's command interface (``cell.commands``);
    ``static_tf``: the node's ``/tf_static``."""

    def __init__(self, sim, static_tf, watchdog=(0.0, None), lockstep_timeout_s=0.0):
        """``watchdog``: the speed scale's (timeout_s, robots or None for all);
        ``lockstep_timeout_s`` > 0: lock-step with their supervisor; see :class:`CellSafety`."""
        self.sim = sim
        self.cell = sim.cell
        self._laser = LaserTopic(self.cell) if self.cell.laser is not None else None
        self._log = log = ThrottledLog()
        self._safety = CellSafety(sim, log, watchdog, lockstep_timeout_s)
        self.lockstep = self._safety.lockstep       # None: the simulator does not wait
        self._arms = {arm.spec.name: ArmTopics(arm, self.cell.commands, log)
                      for arm in self.cell.arms}
        self._transforms = CellTransforms(sim, static_tf)
        self._rviz = CellRviz(sim, static_tf)

    def sync(self):
        """Follow the cell's objects after a removal or a robot loaded (between steps, under
        the lock): the removed robots' topics and descriptions, the laser's topic and the
        removed objects' TF frames go, a loaded robot's come; the markers are re-sent."""
        for name in [n for n in self._arms if n not in self.cell.arm_by_name]:
            self._arms.pop(name).close()
            self._rviz.forget_robot(name)
        for arm in [a for a in self.cell.arms if a.spec.name not in self._arms]:
            self._arms[arm.spec.name] = ArmTopics(arm, self.cell.commands, self._log)
            self._rviz.describe(arm)
        self._safety.sync()
        if self._laser is not None and self.cell.laser is None:
            self._laser.close()
            self._laser = None
        self._transforms.index()
        self._rviz.publish_markers()

    def restart(self):
        """After a rewind (under the lock): the safety topics as built."""
        self._safety.restart()

    def publish(self, step: Step):
        """TF, the laser scan when the cell took one, the joint states."""
        batch, stamp = step.batch, step.stamp
        self._transforms.update_static(step.secs, step.nsecs)
        if batch.wanted(step.tf):
            step.add_tf("cell", self._transforms.message(step.secs, step.nsecs))
        if self._laser is not None:
            self._laser.publish(batch, stamp)
        for arm in self._arms.values():
            arm.publish(batch, stamp)
        self._safety.publish()
