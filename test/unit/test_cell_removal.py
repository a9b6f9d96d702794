"""simRemoveObject/simRemoveModel on the cell's objects (no master): what goes, what stays
indexed right, and what is refused without changing anything. Also the cell's model-side
outputs the ROS faces read: the blob float signals the cell writes after each step (as the
thesis's child script), cleared when their camera goes, and the count of laser scans taken."""
import numpy as np
import pytest

from epuck_vrep_compat.vrep.backend import VrepError


@pytest.fixture
def backend(backend_of):
    return backend_of("merlin_cell.yaml")


def remove(backend, name):
    return backend.remove_object(backend.sim.registry.handle_of(name))


def step(sim, n=3):
    for _ in range(n):
        sim.step()


@pytest.mark.parametrize("name, whole", [("IRB140_link3", "IRB140"), ("SIX_joint2", "SIX"),
                                         ("Bill_head", "Bill")])
def test_a_part_is_refused_and_names_its_whole(backend, name, whole):
    before = len(list(backend.sim.registry.objects()))
    with pytest.raises(VrepError, match=f"remove .*'{whole}' instead"):
        remove(backend, name)
    assert len(list(backend.sim.registry.objects())) == before
    step(backend.sim)


def test_removing_an_arm_takes_its_links_joints_and_mounted_sensors(backend):
    sim = backend.sim
    removed = remove(backend, "IRB140")
    names = ["IRB140", "IRB140_joint1", "IRB140_link6", "Proximity_sensor10"]
    assert all(sim.registry.handle_of(n) == -1 for n in names)
    assert len(removed) > 20
    assert [a.spec.name for a in sim.cell.arms] == ["SIX", "youBot"]
    assert sim.cell.prox_handles == []
    assert not any(sim.world.has(h) for h in removed)
    step(sim)
    # the other arms still move and stay consistent with their stacked link poses
    six = sim.cell.arm_by_name["SIX"]
    positions, _ = sim.cell.link_poses()
    np.testing.assert_allclose(positions[:len(six.link_names)], six.link_position)


def test_removing_one_proximity_sensor_keeps_the_others_on_their_own_rays(backend):
    sim = backend.sim
    remove(backend, "Proximity_sensor12")
    step(sim)
    cell = sim.cell
    assert len(cell.prox_handles) == 10
    for i, h in enumerate(cell.prox_handles):
        obj = sim.registry.get(h)
        assert obj.properties["proximity"]._index == i
        assert cell.prox_rows[i] == cell._link_row("IRB140_link3")[1]


def test_removing_the_operator_laser_camera_and_kinect(backend):
    sim = backend.sim
    for name in ("Bill", "Hokuyo_URG_04LX_UG01_ROS", "camera0", "kinect"):
        remove(backend, name)
        step(sim)
    cell = sim.cell
    assert cell.operator is None and cell.laser is None
    assert [c.name for c in cell.camera_specs] == ["camera"]
    assert cell.kinect_depth is None and cell.kinect_rgb is None
    assert all(sim.registry.handle_of(n) == -1 for n in
               ("Bill", "Bill_head", "camera0", "kinect_depth", "kinect_rgb"))
    # without the operator the remaining ceiling camera sees no blob
    assert cell.blobs["camera"][0] == 0


def test_a_static_object_of_the_scene_is_removed_as_before(backend):
    sim = backend.sim
    handle = sim.registry.handle_of("table")
    assert backend.remove_object(handle) == [handle]
    assert not sim.world.has(handle)
    step(sim)


def test_blob_signals_follow_each_step_and_go_with_their_camera(backend):
    sim = backend.sim
    assert sim.signals["float"] == {}              # written by steps only
    for _ in range(3):
        sim.step()
        for camera in sim.cell.camera_specs:
            packet = sim.cell.blobs[camera.name]
            x_topic, y_topic = camera.blob_topics
            if packet[0] >= 1:
                assert backend.signal("float", x_topic) == float(packet[4])
                assert backend.signal("float", y_topic) == float(packet[5])
            else:
                assert x_topic not in sim.signals["float"]
                assert y_topic not in sim.signals["float"]
    assert "Blob_Camera_0_X" in sim.signals["float"]      # camera0 sees the operator at start
    backend.remove_object(sim.registry.handle_of("camera0"))
    with pytest.raises(VrepError):
        backend.signal("float", "Blob_Camera_0_X")


def test_scan_count_counts_the_scans_taken(backend):
    cell = backend.sim.cell
    every = cell._scan_every
    before = cell.scan_count
    for _ in range(4 * every):
        backend.sim.step()
    assert cell.scan_count == before + 4
