"""How many runs one launch serves: the spec's ``runs_per_launch``.

``runs_per_launch: K`` (default 1), or ``{runs: K, alone: [{NAME: VALUE, ...}, ...]}``: a
parameter cell's seeds are run K to a launch, one after the other (the simulator rewound and
the user's nodes started again between them, so that each run's row is the row it gets
launched alone), except in the cells that match an entry of ``alone`` (every NAME set to
VALUE), which run one to a launch: those whose runs change what a rewind cannot restore (an
object removed, a process killed that must stay dead). The runs' keys, rows and resume are
those of runs launched alone. With K > 1 the code's launch files must declare a
``respawn_nodes`` argument (their nodes must start again when the probe ends them between
runs), and runs have no bag (``bag_dir``: one per launch).
"""
from epuck_vrep_compat.experiment.launch_files import RESPAWN_ARG

NAME = "runs_per_launch"


def runs_per_launch(raw, problems, spec):
    """The checked setting: {"runs": K, "alone": [partial cells]}."""
    if raw is None:
        return {"runs": 1, "alone": []}
    if isinstance(raw, int) and not isinstance(raw, bool):
        raw = {"runs": raw}
    if not isinstance(raw, dict):
        problems.add((NAME,), "must be a number of runs (5) or {runs: 5, alone: [cells]}")
        return {"runs": 1, "alone": []}
    for key in sorted(set(raw) - {"runs", "alone"}, key=str):
        problems.add((NAME, key), "unknown key; the keys are alone, runs")
    runs = raw.get("runs", 1)
    if isinstance(runs, bool) or not isinstance(runs, int) or runs < 1:
        problems.add((NAME, "runs"), "must be a whole number >= 1 (runs per launch)")
        runs = 1
    alone = raw.get("alone", [])
    varied = varied_names(spec.get("vary", {}))
    if not isinstance(alone, list) or not all(isinstance(c, dict) and c for c in alone):
        problems.add((NAME, "alone"), "must be a list of mappings {parameter: value, ...}")
        alone = []
    for i, cell in enumerate(alone):
        for name in cell:
            if name not in varied:
                problems.add((NAME, "alone", i, name), "not a varied parameter; they are "
                             f"{', '.join(sorted(varied)) or 'none'}")
    if runs > 1:
        if spec.get("bag_dir") is not None:
            problems.add((NAME,), "runs share a launch: no bags (bag_dir) with more than one")
        for i, entry in enumerate(spec.get("code", [])):
            declared = entry.get("declared")
            if entry.get("kind") == "launch" and declared is not None and \
                    RESPAWN_ARG not in declared:
                problems.add(("code", i, "launch"), f"declares no '{RESPAWN_ARG}' argument, "
                             f"which {NAME} > 1 needs (its nodes start again for each run)")
    return {"runs": runs, "alone": alone}


def varied_names(vary):
    """Every parameter name ``vary`` sets."""
    names = set(vary.get("grid", {}))
    for cell in vary.get("list", []):
        names |= set(cell)
    names |= set(vary.get("random", {}).get("params", {}))
    return names


def chunk_size(setting, cell):
    """How many runs of ``cell`` one launch serves."""
    if any(all(cell.get(k) == v for k, v in match.items()) for match in setting["alone"]):
        return 1
    return setting["runs"]
