"""Where the repository is, written once for every tier. pytest puts ``test/`` on ``sys.path``
(``pythonpath`` in the root's ``pytest.ini``); rostest clients reach this module through
``sim_test_helpers``, which adds ``test/`` itself (rostest runs the files as scripts)."""
import os

REPO = os.path.dirname(os.path.dirname(os.path.realpath(__file__)))


def fixtures_of(tier):
    """The folder of a tier's fixture files: ``test/<tier>/fixtures``."""
    return os.path.join(REPO, "test", tier, "fixtures")
