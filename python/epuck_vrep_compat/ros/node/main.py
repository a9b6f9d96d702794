"""The simulator's entry point (``rosrun epuck_vrep_compat epuck_sim``): the process set up
for thousands of connections, the node started with its parameters, the step loop run until
SIGINT or SIGTERM, then the stop (``stop.py``), which ends the process."""
import sys
import time
import traceback

import rosgraph
import rospy

from epuck_vrep_compat.compat.topics import NODE, NODE_NAME
from epuck_vrep_compat.paths import PackageNotFound, data_path
from epuck_vrep_compat.ros.common.log import serve_logger_services_safely
from epuck_vrep_compat.ros.node.malloc_arenas import (limit_malloc_arenas,
                                                      map_large_buffers)
from epuck_vrep_compat.ros.node.master_watch import EXIT_MASTER_LOST, MasterWatch, master_pid
from epuck_vrep_compat.ros.node.params import ParamError, read_params
from epuck_vrep_compat.ros.node.simulator_node import SimulatorNode
from epuck_vrep_compat.ros.node.stop import EXIT_FAILED, EXIT_STOPPED, StopRequest, stop_node
from epuck_vrep_compat.ros.transport.accept_queue import (handshake_in_own_thread,
                                                          raise_descriptor_limit,
                                                          share_connection_poller,
                                                          widen_accept_queue)
from epuck_vrep_compat.ros.transport.registration import BulkRegistration
from epuck_vrep_compat.scene.scene_file import SceneError


def main():
    limit_malloc_arenas()        # first: before any thread of rospy's takes an arena
    map_large_buffers()          # images and depth buffers given back when freed
    if not rosgraph.is_master_online():
        sys.stderr.write(f"epuck_sim: no ROS master at {rosgraph.get_master_uri()}; start "
                         "roscore, or start the simulator with roslaunch\n")
        return 1
    first_master_pid = master_pid(NODE)
    raise_descriptor_limit()     # one per connection: 14 001 for 1000 robots, all subscribed
    share_connection_poller()    # not one more per topic
    rospy.init_node(NODE_NAME, disable_signals=True)
    stop = StopRequest()         # SIGINT and SIGTERM end the loop, then stop_node
    widen_accept_queue()         # a subscriber to every topic at once loses none
    handshake_in_own_thread()    # and one that stalls in its handshake blocks no other
    serve_logger_services_safely()
    # watching from the start: rospy retries a vanished master forever while registering
    MasterWatch(first_master_pid)
    registration = BulkRegistration()
    try:
        params = read_params(data_path("worlds", "arena.yaml"))
        # the master learns of the topics from a background thread while the node steps
        with registration:
            node = SimulatorNode(params, data_path("models"))
    except (ParamError, SceneError, PackageNotFound) as e:
        rospy.logfatal("epuck_sim cannot start: %s", e)
        time.sleep(0.5)          # let the log line reach /rosout
        return 2
    except OSError as e:         # the master stopped answering while we read parameters
        rospy.logfatal("epuck_sim cannot start: the ROS master at %s stopped answering (%s)",
                       rosgraph.get_master_uri(), e)
        return EXIT_MASTER_LOST
    rospy.loginfo("epuck_sim: %s", params.summary())
    stop.hold_rospy_shutdown()   # from here every way out is stop_node's
    status = EXIT_STOPPED
    try:
        node.spin(stop.requested)
    except BaseException:  # noqa: BLE001 - the node still stops as it should, and says why
        status = EXIT_FAILED
        rospy.logfatal("epuck_sim: the step loop failed:\n%s", traceback.format_exc())
    reason = f"{stop.signal_name or 'the step loop ended'} at t={node.sim.time_s:.3f} s"
    stop_node(node.batch, node.sim.lock, registration, reason, status)     # ends the process
