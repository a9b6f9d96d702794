"""The names list (``~robot_names``): namespaces, the root robot, unusable lists refused."""
import pytest

from epuck_vrep_compat.ros.epuck.profiles import EPUCK_DRIVER, PROFILES, VREP
from epuck_vrep_compat.ros.epuck.robot_names import parse_robot_names, unconventional_names


def test_a_list_and_a_comma_separated_string_give_the_same_names():
    assert parse_robot_names(["epuck_1", "epuck_7"], VREP) == ["epuck_1", "epuck_7"]
    assert parse_robot_names("epuck_1, epuck_7", VREP) == ["epuck_1", "epuck_7"]
    assert parse_robot_names(["/team_a/epuck_1/"], VREP) == ["team_a/epuck_1"]


def test_topics_and_frames_follow_the_names():
    assert VREP.topic("epuck_7", "cmd_vel") == "/epuck_7/cmd_vel"
    assert VREP.frame("epuck_7", "base_link") == "epuck_7/base_link"
    assert EPUCK_DRIVER.topic("team_a/epuck_1", "cmd_vel") == "/team_a/epuck_1/mobile_base/cmd_vel"


def test_the_root_robot_has_root_topics_and_the_single_launch_frames():
    assert parse_robot_names(["/"], EPUCK_DRIVER) == ["/"]
    assert EPUCK_DRIVER.topic("/", "proximity0") == "/proximity0"
    assert EPUCK_DRIVER.topic("/", "cmd_vel") == "/mobile_base/cmd_vel"
    assert EPUCK_DRIVER.frame("/", "base_link") == "epuck_robot_0/base_link"
    assert VREP.frame("/", "base_link") == "ePuck0/base_link"


@pytest.mark.parametrize("value, says", [
    ([], "non-empty"), ("", "non-empty"), (42, "non-empty"), ([3], "3"),
    (["epuck 1"], "epuck 1"), (["1epuck"], "1epuck"), (["ok", ""], "''"),
    (["epuck_1", "epuck_1"], "twice"), (["/", "epuck_1"], "only"),
    (["a//b"], "a//b"), (["epuck-1"], "epuck-1")])
def test_an_unusable_list_is_refused_naming_the_entry(value, says):
    with pytest.raises(ValueError, match=None) as error:
        parse_robot_names(value, EPUCK_DRIVER)
    assert says in str(error.value)


def test_the_root_robot_frames_clash_with_a_robot_of_that_name():
    # "/" is alone anyway; a duplicate frame prefix is caught for any profile
    for profile in PROFILES.values():
        with pytest.raises(ValueError):
            parse_robot_names(["x", "x"], profile)


def test_names_the_original_would_not_give_are_listed_but_accepted():
    names = parse_robot_names(["epuck_robot_3", "leader"], EPUCK_DRIVER)
    assert unconventional_names(names, EPUCK_DRIVER) == ["leader"]
    assert unconventional_names(["ePuck4", "epuck_robot_0"], VREP) == ["epuck_robot_0"]


def test_every_profile_names_a_topic_for_each_of_its_extras():
    for profile in PROFILES.values():
        for role in profile.extras:
            assert profile.topic("r", role).startswith("/r/"), (profile.name, role)
        if "mag_field" in profile.extras:
            assert profile.topic("r", "mag_field_vector") == "/r/mag_field_vector"
