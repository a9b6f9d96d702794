"""The install space runs on its own: `catkin_make install`, then with nothing sourced but
`.ws/install/local_setup.bash` (Debian's ROS under /usr needs no sourcing) both launch files come
up and publish, the thesis's nodes run, every installed node starts, and bag_to_csv converts a
bag. Each test runs its commands in a clean environment (env -i) on a private ROS master, so
nothing of the source tree or the devel space can stand in for a missing installed file
(``install_env`` and ``install_space``: conftest.py)."""
import ast
import os

from repo import REPO

PKG = "epuck_vrep_compat"


def test_only_the_install_space_is_on_the_paths(install_space, install_env):
    out = install_env.run("echo $ROS_PACKAGE_PATH; echo $PYTHONPATH; rospack find "
                          f"{PKG}; python3 -c 'import {PKG}; print({PKG}.__file__)'")
    assert out.returncode == 0, out.stderr
    for line in out.stdout.split():
        for entry in line.split(":"):
            assert not entry.startswith((os.path.join(REPO, ".ws", "src"),
                                         os.path.join(REPO, ".ws", "devel"),
                                         os.path.join(REPO, "python"))), line
    lines = out.stdout.splitlines()
    assert lines[2] == os.path.join(install_space, "share", PKG)
    assert lines[3].startswith(os.path.join(install_space, "lib"))


def test_every_python_package_and_data_folder_is_installed(install_space):
    source = os.path.join(REPO, "python", PKG)
    installed = os.path.join(install_space, "lib", "python3", "dist-packages", PKG)
    for folder, _, files in os.walk(source):
        if "__init__.py" in files:
            rel = os.path.relpath(folder, source)
            for name in files:
                if name.endswith(".py"):
                    assert os.path.isfile(os.path.join(installed, rel, name)), \
                        f"{rel}/{name} is not installed (setup.py's packages?)"
    for data in ("launch", "worlds", "models", "config"):
        for name in os.listdir(os.path.join(REPO, data)):
            path = os.path.join(install_space, "share", PKG, data, name)
            assert os.path.isfile(path) and not os.path.islink(path), path


def _installed_nodes(install_space):
    return sorted(os.listdir(os.path.join(install_space, "lib", PKG)))


def test_every_installed_node_imports_its_module(install_space, install_env):
    """Each rosrun executable's module (and so its imports) resolves in the install space."""
    scripts = os.path.join(REPO, "scripts")
    assert _installed_nodes(install_space) == sorted(os.listdir(scripts))
    modules = []
    for name in sorted(os.listdir(scripts)):
        tree = ast.parse(open(os.path.join(scripts, name)).read())
        modules += [n.module for n in ast.walk(tree)
                    if isinstance(n, ast.ImportFrom) and n.module.startswith(PKG)]
    code = "import importlib; " + "; ".join(f"importlib.import_module('{m}')" for m in modules)
    out = install_env.run(f"python3 -c \"{code}\"")
    assert out.returncode == 0, out.stderr


def test_epucks_launch_publishes_and_a_bag_becomes_csv(install_env):
    install_env.launch(f"{PKG} epucks.launch n:=2")
    for topic in ("/ePuck0/proximity0", "/ePuck1/proximity7", "/ePuck1/imu", "/tf"):
        install_env.wait_for_message(topic)
    out = install_env.run("rosbag record -q -O run.bag --duration=3 /ePuck0/imu /clock",
                          timeout=60)
    assert out.returncode == 0, out.stderr
    out = install_env.run(f"rosrun {PKG} bag_to_csv run.bag --outdir csv", timeout=120)
    assert out.returncode == 0, out.stdout + out.stderr
    csv = os.path.join(install_env.tmp, "csv")
    files = os.listdir(csv)
    assert any(f.endswith(".csv") for f in files), files


def test_merlin_cell_launch_with_the_thesis_nodes(install_env):
    install_env.launch(f"{PKG} merlin_cell.launch")
    install_env.wait_for_message("/IRB140/joint_states")
    install_env.wait_for_message("/vrep/front_scan")
    # the thesis's nodes are /vrep clients: a message here means a node ran end to end
    out = install_env.wait_for_message("/Irb_PosOrAss")
    assert "posOrAssGiunto, length: 6" in out      # the IRB 140's six joints
    install_env.wait_for_message("/prox_data")
