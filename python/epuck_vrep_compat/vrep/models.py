"""V-REP's calls that add and remove objects while the simulation runs: simLoadModel,
simCopyPasteObjects, simRemoveModel and simRemoveObject, on our scene.

A part of :class:`~epuck_vrep_compat.vrep.backend.VrepBackend`: it reads the simulation and
``models`` (a :class:`~epuck_vrep_compat.scene.model_files.ModelLibrary`, or None) and resolves
objects through the objects part. What can be added is a whole robot (a model file, loaded by
the simulation's extension for its kind of robot, or a copy of an e-puck's base object, by
``sim.epucks``); what can be removed is a whole robot (through its base object) or a static
scene object. A new robot is named as V-REP names a pasted model (the scene's
largest suffix plus one) and placed where it touches nothing. Failures raise
:class:`VrepError` and change nothing.
"""
from epuck_vrep_compat.scene.model_files import ModelFileError
from epuck_vrep_compat.vrep.errors import VrepError


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
        """simLoadModel: the new robot, as the simulation's extension that loads the model
        built it (its ``root`` is its base object; an e-puck's parts). ``model``: the file as
        :meth:`read_model` read it (read here when None). The simulation's listeners (the
        faces) then follow, as after any robot added."""
        if model is None:
            model = self.read_model(file_name)
        try:
            robot = self.sim.load_model(model)
        except ValueError as e:                 # SceneError: the arena is full
            raise VrepError(f"model '{file_name}' not loaded: {e}") from None
        if robot is None:
            raise VrepError(f"model '{file_name}' not loaded: nothing in this scene loads "
                            f"'{model.robot}' models (a scene without a cell)")
        return robot

    def copy_paste(self, handles):
        """simCopyPasteObjects: each handle must be a robot's base object, and each such robot
        gets a copy beside it. Returns (objects copied, handles of every new object)."""
        unique = list(dict.fromkeys(int(h) for h in handles))
        bases = [self._robot_base(h, "copied") for h in unique]
        added = []
        epucks = self.sim.epucks
        try:
            for base in bases:
                x, y, yaw = epucks.swarm.poses[epucks.robot_index(base.robot)]
                added.append(epucks.add_robot((x, y), float(yaw)))
        except ValueError as e:                 # SceneError: the arena is full
            for parts in added:                 # all or nothing
                epucks.remove_robot(parts.root.robot)
            raise VrepError(f"copy of '{base.name}' not added: {e}") from None
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
