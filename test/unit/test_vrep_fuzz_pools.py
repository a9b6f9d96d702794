"""The /vrep fuzz's protection of the objects it must keep (issue 27): ``Pools.without`` took
the protected robots out of the scene's handle pools only, while a handle field also draws the
extremes, V-REP's constants, 0-19 and any integer; in the third round of
``bench/fuzz_memory.py`` on the cell, ``simRosRemoveModel`` drew the IRB 140's handle from
those and removed it, and the suite then found ``/IRB140/joint_states`` silent (the simulator
had rightly unadvertised it). A protected handle is now never drawn for a handle field, by any
of its strategies; other fields keep every value."""
import os
import sys

from hypothesis import HealthCheck, find, given, settings
import hypothesis.strategies as st

from repo import REPO

sys.path.insert(0, os.path.join(REPO, "test", "rostest"))
import test_vrep_fuzz as fuzz  # noqa: E402 - the rostest's own module

PROTECTED = {3, 7, 12}     # small handles: 0-19 are among the constants every int field draws
POOLS = fuzz.Pools({"robots": [3, 7, 12, 40], "static": [5, 41], "links": [8, 9]},
                   [["IRB140", "SIX"]], {"data types": list(range(-1, 21))})
DRAWS = settings(derandomize=True, max_examples=300, deadline=None, database=None,
                 suppress_health_check=list(HealthCheck))


def test_without_the_filter_a_handle_field_draws_protected_small_handles():
    """The defect: the handle pools alone did not keep 3, 7 and 12 out."""
    loose = fuzz.Pools(POOLS.without(PROTECTED).handle_kinds, POOLS.name_kinds, POOLS.hinted)
    for h in PROTECTED:
        assert find(fuzz.int_strategy("int32", loose, "handle"), lambda v, h=h: v == h,
                    settings=settings(database=None, max_examples=5000)) == h


@DRAWS
@given(st.data())
def test_a_handle_field_never_draws_a_protected_handle(data):
    pools = POOLS.without(PROTECTED).for_service("simRosRemoveModel")
    assert data.draw(fuzz.int_strategy("int32", pools, "handle")) not in PROTECTED
    handles = data.draw(fuzz.field_strategy("int32[]", pools, "objectHandles"))
    assert not PROTECTED & set(handles[:10])


def test_other_fields_keep_every_value():
    pools = POOLS.without(PROTECTED)
    assert pools.excluded == PROTECTED
    assert pools.for_service("simRosCopyPasteObjects").excluded == PROTECTED
    assert find(fuzz.int_strategy("int32", pools, "options"), lambda v: v == 7,
                settings=settings(database=None, max_examples=5000)) == 7
