"""Model files: what ``simRosLoadModel`` can load, and how a V-REP file name finds one.

A model file is a small YAML file (see ``models/ePuck.yaml``): ``robot`` (the model it
instantiates: ``epuck``, or ``cell_robot`` for a URDF robot of the industrial cell, which also
gives ``urdf`` (relative to the model file), ``name`` (its base object's), ``mobile`` and
``height_m`` (its base's height); see ``models/IRB140.yaml``), ``aliases`` (other file names that load it, e.g.
V-REP's ``e-puck.ttm``), ``position_m`` and ``yaw_rad`` (the robot goes to the free place
nearest to that point). A request names a model by

* the path of a model file (``.yaml``) inside one of the library's folders (the package's
  ``models/`` and the folders the user lists, ``~model_dirs``), or
* a file name whose last component, ``<stem>`` or ``<stem>.ttm`` or ``<stem>.yaml``, names the
  file ``<stem>.yaml`` of a library folder (the first that has it), or is one of a library
  file's aliases. V-REP clients pass paths of ``.ttm`` files
  (``models/robots/mobile/e-puck.ttm``); their folders do not matter here.

Any caller that reaches the ROS master may call ``simRosLoadModel``, so a path outside the
library's folders is refused (its file is never opened), and no error quotes a file's
contents (a YAML error gives the line and column only). Anything else, and a file over
:data:`MAX_MODEL_FILE_BYTES`, raises :class:`ModelFileError` with the reason. Reading touches
no simulation state: ``simRosLoadModel`` reads and checks the file before it takes the
simulation lock.
"""
import os
from dataclasses import dataclass
from typing import Tuple

from epuck_vrep_compat.scene.validation import SceneError, number, numbers, only, read_yaml

ROBOTS = ("epuck", "cell_robot")
_EXTENSIONS = (".ttm", ".yaml")
MAX_MODEL_FILE_BYTES = 64 * 1024     # ours are a few hundred bytes; parsing more takes seconds


class ModelFileError(ValueError):
    """A model that cannot be loaded; the message says why."""


@dataclass(frozen=True)
class ModelFile:
    """A model file, read and checked: the robot it loads and where it goes."""
    path: str
    robot: str = "epuck"
    position_m: Tuple[float, float] = (0.0, 0.0)
    yaw_rad: float = 0.0
    urdf: str = ""             # cell_robot: absolute path of its URDF
    name: str = ""             # cell_robot: its base object's name (the URDF's root link)
    mobile: bool = False
    height_m: float = 0.0


class ModelLibrary:
    """The model files of the library's folders (the package's ``models/`` first, then the
    user's), read when asked for."""

    def __init__(self, directory: str, more_directories=()):
        self.directories = [directory] + [d for d in more_directories if d]
        self.directory = directory

    def inside(self, path: str) -> bool:
        """Whether ``path`` (symbolic links resolved) lies in one of the library's folders."""
        real = os.path.realpath(path)
        return any(os.path.commonpath([real, os.path.realpath(d)]) == os.path.realpath(d)
                   for d in self.directories)

    def resolve(self, file_name: str) -> ModelFile:
        if not file_name.strip():
            raise ModelFileError("the model file name is empty")
        if file_name.endswith(".yaml") and os.path.isabs(file_name):
            if not self.inside(file_name):
                raise ModelFileError(
                    f"model file '{file_name}' is outside the model folders "
                    f"({', '.join(self.directories)}); list its folder in ~model_dirs")
            if os.path.isfile(file_name):
                return read_model_file(file_name)
        base = file_name.replace("\\", "/").rsplit("/", 1)[-1]
        stem = next((base[:-len(e)] for e in _EXTENSIONS if base.endswith(e)), base)
        for directory in self.directories:
            own = os.path.join(directory, stem + ".yaml")
            if stem and os.path.isfile(own):
                return read_model_file(own)
        for path in self._files():
            if base in _aliases(path):
                return read_model_file(path)
        known = ", ".join(self.names()) or "none"
        raise ModelFileError(f"model file '{file_name}' is not known (models: {known})")

    def names(self):
        """Every name that loads a model of the library, for messages and the README."""
        out = []
        for path in self._files():
            stem = os.path.basename(path)[:-len(".yaml")]
            out += [stem + ".ttm"] + list(_aliases(path))
        return out

    def _files(self):
        out = []
        for directory in self.directories:
            try:
                entries = sorted(os.listdir(directory))
            except OSError:
                continue
            out += [os.path.join(directory, e) for e in entries if e.endswith(".yaml")]
        return out


def read_model_file(path: str) -> ModelFile:
    data = _load(path)
    try:
        only(data, {"robot", "aliases", "position_m", "yaw_rad", "urdf", "name", "mobile",
                    "height_m"}, path)
        robot = data.get("robot")
        if robot not in ROBOTS:
            raise SceneError(f"{path}: robot must be one of {list(ROBOTS)}, got {robot!r}")
        aliases = data.get("aliases", [])
        if not isinstance(aliases, list) or not all(isinstance(a, str) for a in aliases):
            raise SceneError(f"{path}: aliases must be a list of file names, got {aliases!r}")
        position = tuple(numbers(data.get("position_m", [0.0, 0.0]), 2, f"{path}: position_m"))
        yaw = number(data.get("yaw_rad", 0.0), f"{path}: yaw_rad")
        cell = _cell_robot(data, path) if robot == "cell_robot" else {}
    except SceneError as e:
        raise ModelFileError(str(e)) from None
    return ModelFile(path, robot, position, yaw, **cell)


def _cell_robot(data, path):
    """The cell robot's fields: its URDF (which must exist), name, mobility and height."""
    urdf, name = data.get("urdf"), data.get("name")
    if not isinstance(urdf, str) or not isinstance(name, str) or not name:
        raise SceneError(f"{path}: a cell_robot needs 'urdf' and 'name' (strings)")
    urdf = os.path.join(os.path.dirname(os.path.abspath(path)), urdf)
    if not os.path.isfile(urdf):
        raise SceneError(f"{path}: urdf '{urdf}' does not exist")
    mobile = data.get("mobile", False)
    if not isinstance(mobile, bool):
        raise SceneError(f"{path}: mobile must be true or false")
    return dict(urdf=urdf, name=name, mobile=mobile,
                height_m=number(data.get("height_m", 0.0), f"{path}: height_m"))


def _aliases(path: str):
    try:
        aliases = _load(path).get("aliases", [])
    except ModelFileError:
        return ()                  # a broken file loads under its own name only (and fails)
    return tuple(a for a in aliases if isinstance(a, str)) if isinstance(aliases, list) else ()


def _load(path: str) -> dict:
    try:
        size = os.path.getsize(path)
    except OSError as e:
        raise ModelFileError(f"cannot read model file '{path}': {e.strerror}") from None
    if size > MAX_MODEL_FILE_BYTES:
        raise ModelFileError(f"model file '{path}' has {size} bytes; a model file has at most "
                             f"{MAX_MODEL_FILE_BYTES}")
    try:
        data = read_yaml(path, "model file", quote=False)
    except SceneError as e:
        raise ModelFileError(str(e)) from None
    if not isinstance(data, dict):
        raise ModelFileError(f"model file '{path}': the top level must be a mapping")
    return data
