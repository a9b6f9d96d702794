"""Where the package's data lives: models, worlds, URDFs and configs are found in the package's
folder as ROS finds it (rospkg: the source folder in a devel space, ``share/epuck_vrep_compat``
in an install space), never relative to a source file, which holds only in the source tree."""
import functools
import os

PACKAGE = "epuck_vrep_compat"


class PackageNotFound(RuntimeError):
    """ROS cannot find the package (no workspace sourced): its data cannot be found either."""


@functools.lru_cache(maxsize=None)
def package_dir() -> str:
    """The package's folder (with ``models/``, ``worlds/``, ``config/``, ``launch/``)."""
    import rospkg
    try:
        return rospkg.RosPack().get_path(PACKAGE)
    except rospkg.ResourceNotFound:
        raise PackageNotFound(
            f"ROS cannot find the package {PACKAGE} (ROS_PACKAGE_PATH="
            f"{os.environ.get('ROS_PACKAGE_PATH', '')!r}); source the workspace's setup.bash "
            "(devel or install space) first") from None


def data_path(*parts: str) -> str:
    """A file or folder of the package: ``data_path("models", "irb140.urdf")``."""
    return os.path.join(package_dir(), *parts)
