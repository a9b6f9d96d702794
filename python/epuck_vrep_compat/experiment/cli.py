"""``rosrun epuck_vrep_compat experiment run SPEC.yaml [--out DIR] [--scheduler ADDR]
[--workers K]``, ``experiment report DIR`` and ``experiment check SPEC.yaml``.

Exit status: 0 every run ok, 1 some runs failed (they are rows of the results all the same),
2 an unusable spec or command line (nothing ran), 130 interrupted (what finished is kept;
the same command resumes).
"""
import argparse
import os
import sys

from epuck_vrep_compat.experiment import engine, plan, report, results, spec as spec_mod


def parse(argv):
    parser = argparse.ArgumentParser(prog="experiment", description=__doc__.split("\n\n")[0])
    sub = parser.add_subparsers(dest="command", required=True)
    run = sub.add_parser("run", help="run every run of a spec not yet in the results folder")
    run.add_argument("spec", help="the experiment spec (YAML)")
    run.add_argument("--out", help="results folder (default: results/<name>)")
    run.add_argument("--scheduler", help="a Dask scheduler's address, e.g. tcp://host:8786 "
                                         "(default: a local cluster)")
    run.add_argument("--workers", type=int, help="local cluster size (default: one per core)")
    run.add_argument("--seeds", type=int, metavar="N",
                     help="only the spec's first N seeds (a small try; the rows are the same "
                          "as in the full experiment's and are kept for it)")
    rep = sub.add_parser("report", help="rebuild the summary, plots and report.md of a folder")
    rep.add_argument("out", help="results folder")
    check = sub.add_parser("check", help="check a spec and list its runs; runs nothing")
    check.add_argument("spec")
    args = parser.parse_args(argv)
    for option in ("workers", "seeds"):
        if getattr(args, option, None) is not None and getattr(args, option) < 1:
            parser.error(f"--{option} must be at least 1")
    return args


def spec_info(spec):
    return {"name": spec["name"], "spec_hash": spec["hash"],
            "description": spec.get("description", ""),
            "params": sorted({n for cell in plan.cells(spec["vary"]) for n in cell}),
            "metrics": None, "reference": spec.get("reference") or {}}


def seeds_note(asked, seeds):
    """What ``--seeds asked`` does when the spec has fewer ``seeds``, or None: it only takes
    the spec's first N seeds and adds none (the spec says which seeds an experiment has)."""
    if asked <= len(seeds):
        return None
    return (f"--seeds {asked} asks for more seeds than the spec has ({len(seeds)}): it runs "
            f"those {len(seeds)} and no new ones; to run more, raise the spec's 'seeds' "
            f"(e.g. 'seeds: {asked}') and run the same command again (the rows already there "
            f"are kept)")


def write_report(store, spec):
    info = spec_info(spec)
    rows = store.rows
    info["metrics"] = sorted({k[len("metric."):] for r in rows for k in r
                              if k.startswith("metric.")})
    report.write_report(store.out_dir, rows, info)


def main(argv=None):
    args = parse(sys.argv[1:] if argv is None else argv)
    if args.command == "report":
        store = results.ResultStore(args.out)
        if not os.path.isfile(os.path.join(args.out, "spec.json")):
            print(f"experiment: {args.out} holds no experiment (no spec.json)", file=sys.stderr)
            return 2
        write_report(store, store.load_spec())
        print(f"experiment: report written to {os.path.join(args.out, 'report.md')}")
        return 0
    try:
        spec = spec_mod.load(args.spec)
    except spec_mod.SpecError as e:
        print(f"experiment: {e}", file=sys.stderr)
        return 2
    if getattr(args, "seeds", None):
        note = seeds_note(args.seeds, spec["seeds"])
        if note:
            print(f"experiment: {note}", file=sys.stderr)
        spec["seeds"] = spec["seeds"][:args.seeds]
    tasks = plan.tasks(spec)
    if args.command == "check":
        print(f"experiment: {args.spec} is valid: {len(plan.cells(spec['vary']))} cell(s) x "
              f"{len(spec['seeds'])} seed(s) = {len(tasks)} run(s), spec hash {spec['hash']}")
        return 0
    store = results.ResultStore(args.out or os.path.join("results", spec["name"]))
    print(f"experiment: {spec['name']}: {len(tasks)} run(s), {len(store.done & {t.key for t in tasks})}"
          f" already in {store.out_dir}", file=sys.stderr)
    try:
        _ok, failed = engine.run(spec, store, args.scheduler, args.workers)
    except KeyboardInterrupt:
        print(f"experiment: interrupted; {len(store.rows)} run(s) kept in {store.out_dir}, the "
              "same command resumes", file=sys.stderr)
        return 130
    write_report(store, spec)
    n_failed = sum(r["status"] != "ok" for r in store.rows)
    print(f"experiment: {len(store.rows)} run(s) in {store.out_dir} ({n_failed} failed); "
          f"report: {os.path.join(store.out_dir, 'report.md')}")
    return 1 if n_failed else 0
