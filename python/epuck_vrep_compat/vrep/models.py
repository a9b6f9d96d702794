"""V-REP's calls that add and remove objects while the simulation runs: simLoadModel,
simCopyPasteObjects, simRemoveModel and simRemoveObject, on our scene.

A part of :class:`~epuck_vrep_compat.vrep.backend.VrepBackend`: it reads the simulation and
``models`` (a :class:`~epuck_vrep_compat.scene.model_files.ModelLibrary`, or None) and resolves
objects through the objects part. What can be added is a whole robot (a model file, or a
copy of a robot's base object); what can be removed is a whole robot (through its base object)
or a static scene object. A new robot is named as V-REP names a pasted model (the scene's
largest suffix plus one) and placed where it touches nothing. Failures raise
:class:`VrepError` and change nothing.
"""
from collections import namedtuple

from epuck_vrep_compat.scene.model_files import ModelFileError
from epuck_vrep_compat.vrep.errors import VrepError

LoadedRobot = namedtuple("LoadedRobot", "root")    # a cell robot loaded: its base object


class VrepModels:
    """Whole robots added (model files, copies) and objects removed while the simulation runs."""

    def __init__(self, objects, models=None):
        """``objects``: the :class:`~epuck_vrep_compat.vrep.objects.VrepObjects` part;
        ``models``: the ModelLibrary simLoadModel reads (None: loading always fails)."""
        self.objects = objects
        self.sim = objects.sim
        self.models = models

    def read_model(self, file_name: str):
        """The model file simLoadModel would load, read and checked; needs no simulation lock
        (it reads files only), so a caller reads it before taking the lock."""
        if self.models is None:
            raise VrepError("this simulator was started without a model folder")
        try:
            return self.models.resolve(file_name)
        except ModelFileError as e:
            raise VrepError(str(e)) from None

    def load_model(self, file_name: str, model=None):
        """simLoadModel: the new robot's parts (base object first). ``model``: the file as
        :meth:`read_model` read it (read here when None)."""
        if model is None:
            model = self.read_model(file_name)
        if model.robot != "epuck":
            return LoadedRobot(self._load_by_extension(model, file_name))
        return self._add_robot(model.position_m, model.yaw_rad, f"model '{file_name}'")

    def copy_paste(self, handles):
        """simCopyPasteObjects: each handle must be a robot's base object, and each such robot
        gets a copy beside it. Returns (objects copied, handles of every new object)."""
        unique = list(dict.fromkeys(int(h) for h in handles))
        bases = [self._robot_base(h, "copied") for h in unique]
        added = []
        try:
            for base in bases:
                x, y, yaw = self.sim.swarm.poses[self.sim.robot_index(base.robot)]
                added.append(self._add_robot((x, y), yaw, f"copy of '{base.name}'"))
        except VrepError:
            for parts in added:                 # all or nothing
                self.sim.remove_robot(parts.root.robot)
            raise
        return len(unique), [obj.handle for parts in added for obj in parts.parts.values()]

    def remove_object(self, handle: int):
        """simRemoveObject and simRemoveModel: a robot's base object takes the whole robot with
        it; a static scene object leaves the collision world. Returns the removed handles."""
        obj = self.objects.get(handle)
        try:
            return self.sim.remove_object(obj.handle)
        except ValueError as e:
            raise VrepError(str(e)) from None

    def _robot_base(self, handle: int, what: str):
        obj = self.objects.get(handle)
        if obj.robot is None or obj.part != "root":
            owner = f"a part of robot {obj.robot}" if obj.robot else "a static scene object"
            raise VrepError(f"object {handle} ('{obj.name}') is {owner}, not a robot's base "
                            f"object: only whole robots can be {what}")
        return obj

    def _load_by_extension(self, model, file_name):
        """A model an extension of the simulation builds (a cell robot): its base object; the
        simulation's listeners (the faces) then follow, as after any robot added."""
        try:
            base = next(filter(None, (e.load_model(model) for e in self.sim.extensions)), None)
        except ValueError as e:
            raise VrepError(f"model '{file_name}' not loaded: {e}") from None
        if base is None:
            raise VrepError(f"model '{file_name}' not loaded: nothing in this scene loads "
                            f"'{model.robot}' models (a scene without a cell)")
        for listener in list(self.sim.listeners):
            listener()
        return base

    def _add_robot(self, near_xy, yaw_rad, what):
        try:
            return self.sim.add_robot(near_xy, float(yaw_rad))
        except ValueError as e:                 # SceneError: the arena is full
            raise VrepError(f"{what} not added: {e}") from None
