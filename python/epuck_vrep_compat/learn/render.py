"""A world drawn top-down as an RGB array, in numpy: the floor, the walls, the cylinders, each
robot as a disc with a dot at its front (agents blue, scripted robots red), its IR activations
as short grey ticks. For ``render()`` of the environments and for videos."""
import numpy as np

from epuck_vrep_compat.learn.tasks import ARENA_SIDE_M, BODY_RADIUS_M, WALL_THICKNESS_M

FLOOR = (235, 235, 228)
WALL = (90, 90, 90)
CYLINDER = (150, 110, 60)
AGENT = (40, 90, 200)
SCRIPTED = (200, 60, 50)
FRONT = (255, 255, 255)


class ArenaPainter:
    """Pixels of the square arena at ``size`` x ``size``; +x to the right, +y up."""

    def __init__(self, sensor_yaws=(), size: int = 256):
        self.size = size
        self.sensor_yaws = tuple(sensor_yaws)      # the IR sensors' directions [rad]
        self.extent = 0.5 * ARENA_SIDE_M + WALL_THICKNESS_M
        centres = (np.arange(size) + 0.5) / size * 2.0 * self.extent - self.extent
        self.x = centres[None, :]
        self.y = centres[::-1, None]

    def _disc(self, image, x, y, radius, colour):
        image[(self.x - x) ** 2 + (self.y - y) ** 2 <= radius ** 2] = colour

    def draw(self, cylinders, poses, agent_rows, activations=None) -> np.ndarray:
        """(size, size, 3) uint8 of one world: cylinders, poses (R, 3), the agents' rows,
        optional IR activations (R, 8) drawn as ticks at the sensors' directions."""
        image = np.empty((self.size, self.size, 3), dtype=np.uint8)
        image[:] = WALL
        half = 0.5 * ARENA_SIDE_M
        inside = (np.abs(self.x) <= half) & (np.abs(self.y) <= half)
        image[inside] = FLOOR
        for c in cylinders:
            self._disc(image, c.x, c.y, c.radius, CYLINDER)
        for r, (x, y, yaw) in enumerate(np.asarray(poses, float)):
            self._disc(image, x, y, BODY_RADIUS_M, AGENT if r in agent_rows else SCRIPTED)
            front = 0.6 * BODY_RADIUS_M
            self._disc(image, x + front * np.cos(yaw), y + front * np.sin(yaw),
                       0.25 * BODY_RADIUS_M, FRONT)
            if activations is not None:
                for k, angle in enumerate(self.sensor_yaws):
                    reach = BODY_RADIUS_M + 0.005 + 0.03 * float(activations[r][k])
                    self._disc(image, x + reach * np.cos(yaw + angle),
                               y + reach * np.sin(yaw + angle), 0.004, WALL)
        return image
