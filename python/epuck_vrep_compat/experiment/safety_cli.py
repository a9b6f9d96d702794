"""``rosrun epuck_vrep_compat safety_bench run|report|coverage``: the speed-and-separation
monitoring benchmark (``experiments/safety_ssm.yaml``, docs/safety_benchmark.md) on the
experiment runner.

``run [--out DIR] [--walks N] [--cell-walks M] [--workers K] [--scheduler ADDR]
[--no-coverage]``: our supervisor at its defaults without a fault (the spec's first cell) over
the first N seeds (walks), every monitor x fault cell over the first M, the coverage maps
(``experiments/safety_ssm/coverage.yaml``) unless ``--no-coverage``, all on one cluster (the
longest launches first: ``engine.run_all``), then ``DIR/report.md``.
The runs' results are in ``DIR/walks`` and ``DIR/coverage`` (experiment folders: the same
command resumes). ``report DIR`` rebuilds the report; ``coverage DIR`` makes only the maps.
Exit status as ``experiment``'s: 0 all ok, 1 some runs failed, 2 unusable, 130 interrupted.
"""
import argparse
import json
import os
import sys
import time

import rospkg
import yaml

from epuck_vrep_compat.experiment import coverage_maps, engine, plan, report_safety, results
from epuck_vrep_compat.experiment import spec as spec_mod
from epuck_vrep_compat.experiment.cli import write_report

WALKS, CELL_WALKS = 200, 5
WORKERS_PER_CORE = 2        # the lock-step's round trips leave a walk about half a core


def shipped(name):
    return os.path.join(rospkg.RosPack().get_path("epuck_vrep_compat"), "experiments", name)


def COVERAGE_SPEC():        # noqa: N802  (a path, found when asked: rospkg needs the workspace)
    return shipped(os.path.join("safety_ssm", "coverage.yaml"))


def parse(argv):
    parser = argparse.ArgumentParser(prog="safety_bench", description=__doc__.split("\n\n")[0])
    sub = parser.add_subparsers(dest="command", required=True)
    run = sub.add_parser("run", help="run the benchmark (what is not yet in DIR)")
    run.add_argument("--out", default=os.path.join("results", "safety_ssm"))
    run.add_argument("--spec", default=shipped("safety_ssm.yaml"))
    run.add_argument("--walks", type=int, default=WALKS,
                     help=f"walks of the spec's first cell (default {WALKS})")
    run.add_argument("--cell-walks", type=int, default=CELL_WALKS,
                     help=f"walks of every other cell (default {CELL_WALKS})")
    run.add_argument("--workers", type=int,
                     help="local worker processes (default: two per core: a walk in lock-step "
                          "keeps about half a core busy)")
    run.add_argument("--scheduler")
    run.add_argument("--no-coverage", action="store_true")
    for name in ("report", "coverage"):
        sub.add_parser(name).add_argument("out")
    args = parser.parse_args(argv)
    for option in ("walks", "cell_walks", "workers"):
        if getattr(args, option, None) is not None and getattr(args, option) < 1:
            parser.error(f"--{option.replace('_', '-')} must be at least 1")
    return args


def run_specs(jobs, args):
    """Runs loaded specs, each into its folder ((spec, folder) pairs), on one cluster (their
    launches together, the longest first), then each folder's generic report; True when every
    run is ok."""
    stores = [(spec, results.ResultStore(folder)) for spec, folder in jobs]
    workers = args.workers or (None if args.scheduler
                               else WORKERS_PER_CORE * (os.cpu_count() or 1))
    engine.run_all(stores, args.scheduler, workers)
    for spec, store in stores:
        write_report(store, spec)
    return all(r["status"] == "ok" for _, store in stores for r in store.rows)


def walk_specs(args):
    """The walks' specs (the first cell over ``--walks`` seeds, every cell over
    ``--cell-walks``), each with its folder: both ``DIR/walks``."""
    spec = spec_mod.load(args.spec)
    seeds = spec["seeds"]
    if len(seeds) < max(args.walks, args.cell_walks):
        first = seeds[0]
        seeds = list(range(first, first + max(args.walks, args.cell_walks)))
    headline = dict(spec, seeds=seeds[:args.walks],
                    vary={"list": plan.cells(spec["vary"])[:1]})
    folder = os.path.join(args.out, "walks")
    return [(headline, folder), (dict(spec, seeds=seeds[:args.cell_walks]), folder)]


def coverage_spec(out_dir):
    """The coverage runs' spec (bags in ``out_dir/coverage/bags``) and its folder."""
    folder = os.path.join(out_dir, "coverage")
    return dict(spec_mod.load(COVERAGE_SPEC()), bag_dir=os.path.join(folder, "bags")), folder


def coverage(out_dir, args=None):
    """The coverage runs alone and a PNG per layout; returns (all ok, the PNGs' paths)."""
    args = args or argparse.Namespace(scheduler=None, workers=None)
    ok = run_specs([coverage_spec(out_dir)], args)
    return ok, draw_maps(out_dir)


def draw_maps(out_dir):
    """A coverage PNG for each layout whose bag is in ``out_dir/coverage``."""
    folder = os.path.join(out_dir, "coverage")
    maps = []
    for row in results.ResultStore(folder).rows:
        bag = os.path.join(folder, "bags", f"{row['run_key']}.bag")
        world = os.path.join(os.path.dirname(COVERAGE_SPEC()), row.get("param.sim.world", ""))
        if row["status"] != "ok" or not os.path.isfile(bag):
            continue
        name = os.path.splitext(os.path.basename(world))[0].replace("_coverage", "")
        with open(world) as f:
            size = yaml.safe_load(f)["arena"]["size_m"][:2]
        error, cameras = coverage_maps.grid(*coverage_maps.read_bag(bag), size)
        path = os.path.join(out_dir, f"coverage_{name}.png")
        coverage_maps.draw(path, world, error, cameras, f"{name} layout")
        maps.append(path)
    return sorted(maps)


def write(out_dir):
    rows = results.ResultStore(os.path.join(out_dir, "walks")).rows
    maps = sorted(os.path.join(out_dir, f) for f in os.listdir(out_dir)
                  if f.startswith("coverage_") and f.endswith(".png"))
    return report_safety.write(out_dir, rows, maps=maps, wall_s=_timing(out_dir).get("wall_s"))


def _timing(out_dir):
    """``timing.json``: the wall time of every invocation that ran walks into ``out_dir``,
    summed (a resumed benchmark's is the total, not its last part's), and their count."""
    path = os.path.join(out_dir, "timing.json")
    if not os.path.isfile(path):
        return {}
    with open(path) as f:
        return json.load(f)


def add_timing(out_dir, wall_s, walks, cell_walks):
    """Adds an invocation's wall time to ``timing.json`` (see :func:`_timing`)."""
    os.makedirs(out_dir, exist_ok=True)
    before = _timing(out_dir)
    with open(os.path.join(out_dir, "timing.json"), "w") as f:
        json.dump({"wall_s": before.get("wall_s", 0.0) + wall_s,
                   "invocations": before.get("invocations", 1 if before else 0) + 1,
                   "walks": walks, "cell_walks": cell_walks}, f)


def main(argv=None):
    args = parse(sys.argv[1:] if argv is None else argv)
    try:
        if args.command == "report":
            print(f"safety_bench: {write(args.out)}")
            return 0
        if args.command == "coverage":
            ok, maps = coverage(args.out)
            print(f"safety_bench: {', '.join(maps) or 'no map'}")
            return 0 if ok else 1
        started = time.monotonic()
        jobs = walk_specs(args) + ([] if args.no_coverage else [coverage_spec(args.out)])
        ok = run_specs(jobs, args)
        if not args.no_coverage:
            draw_maps(args.out)
        add_timing(args.out, time.monotonic() - started, args.walks, args.cell_walks)
        print(f"safety_bench: {write(args.out)}")
        return 0 if ok else 1
    except spec_mod.SpecError as e:
        print(f"safety_bench: {e}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("safety_bench: interrupted; the same command resumes", file=sys.stderr)
        return 130
