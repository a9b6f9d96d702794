#!/usr/bin/python3
"""The simulator's cost of the Kinect: one depth buffer (and colour image) as ``/vrep`` serves
it, from the ray casting to the response's bytes, in the MERLIN cell as the tests build it.

Builds ``worlds/merlin_cell.yaml`` (seed ``--seed``, no master), steps it 2 x ``--frames``
times (10 Hz of simulated time at the cell's 20 Hz step, as the safety benchmark's Kinect node
asks) and, after every second step, serves simRosGetVisionSensorDepthBuffer for the Kinect's
depth sensor and simRosGetVisionSensorImage for its colour sensor through the plugin's own
handlers, serialising each response as rospy would. Prints the CPU time (``time.process_time``:
unlike wall time, it does not count other processes' turns on a shared machine) per depth buffer
and per colour image.

``--save FILE`` writes every response's bytes (npz); ``--compare FILE`` checks them bit for bit
against such a file (the check that a faster build changes no image); ``--depth-only`` serves
the depth buffer alone (the safety benchmark's Kinect node asks for nothing else unless its
colour topic has a subscriber; the depth frames are the same either way). With ``--no-serve``
the script only steps: under callgrind, the instructions of a run with and one without, divided
by ``--frames``, are those of one depth buffer (and colour image):

    valgrind --tool=callgrind --callgrind-out-file=/tmp/cg.%p \\
        /usr/bin/python3 bench/kinect_depth.py --frames 10 --depth-only [--no-serve]
    callgrind_annotate /tmp/cg.<pid> | head -40
"""
import argparse
import io
import os
import sys
import time

import numpy as np
from vrep_common import srv

from epuck_vrep_compat.builder.build import SimulationConfig, build_simulation
from epuck_vrep_compat.ros.vrep_plugin.services_devices import (
    get_vision_sensor_depth_buffer, get_vision_sensor_image)
from epuck_vrep_compat.scene.scene_file import load_scene
from epuck_vrep_compat.sim.control import RUNNING, SimulationControl
from epuck_vrep_compat.vrep.backend import VrepBackend

WORLD = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "worlds",
                     "merlin_cell.yaml")


def wire_bytes(response):
    buff = io.BytesIO()
    response.serialize(buff)
    return buff.getvalue()


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--frames", type=int, default=50)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--no-serve", action="store_true", help="step only")
    parser.add_argument("--depth-only", action="store_true",
                        help="serve the depth buffer alone (the safety benchmark's case)")
    parser.add_argument("--save", help="write every response's bytes to this npz")
    parser.add_argument("--compare", help="check every response's bytes against this npz")
    args = parser.parse_args()
    sim = build_simulation(load_scene(WORLD), SimulationConfig([], seed=args.seed))
    backend = VrepBackend(sim, SimulationControl(sim, RUNNING), real_time=False)
    depth_req = srv.simRosGetVisionSensorDepthBufferRequest(
        handle=sim.cell.kinect_depth.handle)
    rgb_req = srv.simRosGetVisionSensorImageRequest(handle=sim.cell.kinect_rgb.handle,
                                                    options=0)
    frames, depth_s, rgb_s = {}, 0.0, 0.0
    for k in range(args.frames):
        sim.step()
        sim.step()
        if args.no_serve:
            continue
        start = time.process_time()
        depth = wire_bytes(get_vision_sensor_depth_buffer(backend, depth_req, []))
        middle = time.process_time()
        depth_s += middle - start
        frames[f"depth{k}"] = np.frombuffer(depth, dtype=np.uint8)
        if not args.depth_only:
            rgb = wire_bytes(get_vision_sensor_image(backend, rgb_req, []))
            rgb_s += time.process_time() - middle
            frames[f"rgb{k}"] = np.frombuffer(rgb, dtype=np.uint8)
    sim.cell.close()
    if args.no_serve:
        return 0
    n = max(args.frames, 1)
    print(f"{args.frames} frames: CPU {1e3 * depth_s / n:.2f} ms a depth buffer, "
          f"{1e3 * rgb_s / n:.2f} ms a colour image")
    if args.save:
        np.savez_compressed(args.save, **frames)
    if args.compare:
        saved = np.load(args.compare)
        both = [k for k in frames if k in saved]
        differ = [k for k in both if not np.array_equal(saved[k], frames[k])]
        print(f"compared {len(both)} responses with {args.compare} ({len(frames) - len(both)} "
              "not in it): " + (f"{len(differ)} differ: {differ[:5]}" if differ
                                else "all bit-identical"))
        return 1 if differ else 0
    return 0


if __name__ == "__main__":
    sys.exit(main())
