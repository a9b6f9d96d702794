"""The test fault hook's face (only with ``~test_fault_hook:=true``; never by default): its
commands as services of the node, and a ``publish`` that raises while the publish fault is on.

* ``~fault/raise_in_step`` (``std_srvs/Empty``): the next step raises;
* ``~fault/block_step`` (``std_srvs/Empty``): the next step blocks for :data:`BLOCK_S` of wall
  time, far past one step's real-time budget;
* ``~fault/raise_in_publish`` (``std_srvs/SetBool``): this face's ``publish`` raises on every
  step while on.

What the node does with each is in ``docs/parameters.md`` (faults); the tests are
``test/rostest/fault_hook.test``.
"""
import rospy
from std_srvs.srv import Empty, EmptyResponse, SetBool, SetBoolResponse

from epuck_vrep_compat.ros.face import Face

BLOCK_S = 1.0          # a blocked step's wall time: 20 steps of 50 ms at real time


class FaultFace(Face):
    """The services arming a :class:`~epuck_vrep_compat.sim.fault_hook.FaultHook`."""

    def __init__(self, hook):
        self._hook = hook
        rospy.Service("~fault/raise_in_step", Empty, self._on_raise_in_step)
        rospy.Service("~fault/block_step", Empty, self._on_block_step)
        rospy.Service("~fault/raise_in_publish", SetBool, self._on_raise_in_publish)

    def _on_raise_in_step(self, _req):
        self._hook.raise_in_next_step()
        return EmptyResponse()

    def _on_block_step(self, _req):
        self._hook.block_next_step(BLOCK_S)
        return EmptyResponse()

    def _on_raise_in_publish(self, req):
        self._hook.set_publish_fault(req.data)
        return SetBoolResponse(True, "on" if req.data else "off")

    def publish(self, step):
        self._hook.check_publish()
