"""The simulation a scene file describes: the e-pucks' :class:`Simulation`, with the scene's
industrial cell as its extension when the scene has a ``cell:`` section.

The one place that joins the two; pybullet is loaded only when a cell is used.
"""
from epuck_vrep_compat.scene.scene_file import Scene
from epuck_vrep_compat.sim.simulation import Simulation


def build_simulation(scene: Scene, robot_names, *args, **kwargs) -> Simulation:
    """A :class:`Simulation` of ``scene`` (arguments as its constructor's). The result's
    ``cell`` attribute is the scene's :class:`~epuck_vrep_compat.cell.cell.Cell`, added to the
    simulation's extensions, or None when the scene has no cell."""
    sim = Simulation(scene, robot_names, *args, **kwargs)
    sim.cell = None
    if scene.cell is not None:
        from epuck_vrep_compat.cell.cell import Cell     # pybullet only when a cell is used
        sim.cell = Cell(sim, scene.cell, sim.seed)
        sim.add_extension(sim.cell)
    return sim
