"""simLoadModel, simCopyPasteObjects, simRemoveModel/simRemoveObject on the backend (no master):
model file names, what each call adds or removes, and failures that change nothing."""
import os

import pytest

from epuck_vrep_compat.compat import vrep_codes as vc
from epuck_vrep_compat.scene.model_files import ModelFileError, ModelLibrary
from epuck_vrep_compat.vrep.backend import VrepBackend, VrepError
from repo import REPO

MODELS = os.path.join(REPO, "models")
EPUCK_YAML = os.path.abspath(os.path.join(MODELS, "ePuck.yaml"))


@pytest.fixture
def backend(backend_of):
    return backend_of("arena.yaml", ["ePuck0", "ePuck1"])


@pytest.mark.parametrize("name", [
    "ePuck", "ePuck.ttm", "ePuck.yaml", "e-puck.ttm", "models/robots/mobile/e-puck.ttm",
    "/opt/V-REP_PRO_EDU/models/robots/mobile/ePuck.ttm", "C:\\V-REP\\models\\e-puck.ttm",
    EPUCK_YAML])
def test_model_names_that_load_the_epuck(name):
    model = ModelLibrary(MODELS).resolve(name)
    assert os.path.samefile(model.path, EPUCK_YAML) and model.robot == "epuck"


@pytest.mark.parametrize("name", ["", "  ", "bubbleRob.ttm", "epuck.ttm", "ePuck.ttm/x",
                                  "/no/such/dir/ePuck2.yaml"])
def test_unknown_model_names_are_refused_with_what_is_known(name):
    with pytest.raises(ModelFileError,
                       match="empty|not known.*ePuck.ttm, e-puck.ttm|outside the model folders"):
        ModelLibrary(MODELS).resolve(name)


def test_a_model_file_of_ones_own_and_a_broken_one(tmp_path):
    own = tmp_path / "corner.yaml"
    own.write_text("robot: epuck\nposition_m: [0.4, -0.4]\nyaw_rad: 1.0\n")
    model = ModelLibrary(MODELS, [str(tmp_path)]).resolve(str(own))
    assert model.position_m == (0.4, -0.4) and model.yaw_rad == 1.0
    library = ModelLibrary(str(tmp_path))
    assert library.resolve("corner.ttm") == model
    (tmp_path / "tank.yaml").write_text("robot: tank\n")
    with pytest.raises(ModelFileError, match="robot must be one of"):
        library.resolve("tank")
    (tmp_path / "typo.yaml").write_text("robot: epuck\npositon_m: [0, 0]\n")
    with pytest.raises(ModelFileError, match="unknown key"):
        library.resolve("typo.ttm")
    (tmp_path / "bad.yaml").write_text("robot: [epuck\n")
    with pytest.raises(ModelFileError, match="not valid YAML"):
        library.resolve("bad")


def test_load_model_adds_a_robot_with_the_next_suffix(backend):
    parts = backend.load_model("e-puck.ttm")
    assert parts.root.name == "ePuck#1" and parts.root.robot == "ePuck2"
    assert backend.object_handle("ePuck#1") == parts.root.handle
    assert backend.object_handle("ePuck_camera#1") == parts.handle("camera")
    assert backend.parent(parts.handle("proxSensor0")) == parts.root.handle
    assert backend.proximity(parts.handle("proxSensor0"))[0] in (0, 1)
    assert len(backend.joints()) == 6
    assert backend.load_model("ePuck").root.name == "ePuck#2"


def test_load_model_failures_change_nothing(backend):
    count = len(backend.sim.registry)
    for name in ("", "rover.ttm"):
        with pytest.raises(VrepError):
            backend.load_model(name)
    assert len(backend.sim.registry) == count
    no_library = VrepBackend(backend.sim, backend.control, True, models=None)
    with pytest.raises(VrepError, match="without a model folder"):
        no_library.load_model("ePuck.ttm")


def test_copy_paste_copies_whole_robots_beside_the_original(backend):
    base = backend.object_handle("ePuck")
    copied, handles = backend.copy_paste([base, base])
    assert copied == 1 and len(handles) == 26
    assert backend.object_name(handles[0]) == "ePuck#1"
    assert [backend.parent(h) for h in handles].count(vc.WORLD) == 1
    original, copy = backend.pose(base)[0], backend.pose(handles[0])[0]
    assert 0.074 <= ((original - copy) ** 2).sum() ** 0.5 < 0.2           # beside it
    assert backend.copy_paste([]) == (0, [])


@pytest.mark.parametrize("what", ["ePuck_proxSensor0", "box0", "Floor"])
def test_copy_paste_refuses_anything_but_robot_bases(backend, what):
    count = len(backend.sim.registry)
    handle = backend.object_handle(what)
    with pytest.raises(VrepError, match="only whole robots can be copied"):
        backend.copy_paste([backend.object_handle("ePuck#0"), handle])
    with pytest.raises(VrepError, match="does not exist"):
        backend.copy_paste([99999])
    assert len(backend.sim.registry) == count and backend.sim.epucks.size == 2


def test_remove_object_takes_robots_whole_and_static_objects_out(backend):
    with pytest.raises(VrepError, match="does not exist"):
        backend.remove_object(99999)
    with pytest.raises(VrepError, match="part of robot ePuck1"):
        backend.remove_object(backend.object_handle("ePuck_leftWheel#0"))
    assert len(backend.remove_object(backend.object_handle("ePuck#0"))) == 26
    with pytest.raises(VrepError, match="does not exist"):
        backend.object_handle("ePuck_camera#0")
    box = backend.object_handle("cylinder0")
    assert backend.remove_object(box) == [box]
    assert not backend.sim.world.has(box)
    assert backend.sim.epucks.robot_names == ["ePuck0"]


def test_a_path_outside_the_model_folders_is_refused_unread(tmp_path):
    """Anyone who reaches the master may call simRosLoadModel: only the library's folders, and
    the path is refused before the file is read (a file that would fail to read, not UTF-8,
    is refused as outside, not as unreadable)."""
    secret = tmp_path / "secret.yaml"
    secret.write_text("robot: epuck\n")
    unreadable = tmp_path / "unreadable.yaml"
    unreadable.write_bytes(b"\xff\xfe robot: epuck\n")
    for name in (str(secret), str(unreadable), str(tmp_path / "missing.yaml"),
                 os.path.join(MODELS, "..", "..", os.path.relpath(str(secret), "/"))):
        with pytest.raises(ModelFileError, match="outside the model folders.*~model_dirs"):
            ModelLibrary(MODELS).resolve(name)
    # a symbolic link in a model folder to a file outside it is outside too
    linked = tmp_path / "models"
    linked.mkdir()
    (linked / "link.yaml").symlink_to(secret)
    with pytest.raises(ModelFileError, match="outside the model folders"):
        ModelLibrary(str(linked)).resolve(str(linked / "link.yaml"))
    # listed, the folder's files load by path and by name, after the package's own
    library = ModelLibrary(MODELS, [str(tmp_path)])
    assert library.resolve(str(secret)).path == str(secret)
    assert library.resolve("secret.ttm").path == str(secret)
    assert os.path.samefile(library.resolve("ePuck.ttm").path, EPUCK_YAML)


def test_errors_never_quote_a_model_files_text(tmp_path):
    (tmp_path / "bad.yaml").write_text("robot: epuck\npassword: [hunter2\n")
    with pytest.raises(ModelFileError) as error:
        ModelLibrary(str(tmp_path)).resolve("bad")
    assert "hunter2" not in str(error.value)
    assert "not valid YAML at line" in str(error.value)
    (tmp_path / "binary.yaml").write_bytes(b"\xff\xfe secret")
    with pytest.raises(ModelFileError, match="not UTF-8") as error:
        ModelLibrary(str(tmp_path)).resolve("binary")
    assert "secret" not in str(error.value)
