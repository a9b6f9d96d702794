"""Where the time went: every tier's and the slowest test files' wall and CPU time, written
after each run as ``timing.md`` (for people, and docs/testing.md) and ``timing.json``; and the
costs the scheduler remembers for the next run (``.ws/suite_costs.json``, from runs that passed
without the stress hog: a job's wall time and CPU time)."""
import glob
import json
import os
import platform
import time

from suite.plan import TIERS as TIER_ORDER

SLOWEST = 30
SHIPPED_COSTS = os.path.join(os.path.dirname(os.path.abspath(__file__)), "costs.json")


def processor():
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown"


def file_times(job, results):
    """{test file: (wall_s, cpu_s)} of one job: from the pytest plugin's records for a pytest
    job over several files, else the job's own wall and CPU time."""
    if len(job.files) > 1 or job.tier in ("core", "unit"):
        spent = {}
        for path in glob.glob(os.path.join(results, "timing", job.name, "*.json")):
            with open(path, encoding="utf-8") as f:
                for file, (wall, cpu) in json.load(f)["files"].items():
                    total = spent.setdefault(file, [0.0, 0.0])
                    total[0] += wall
                    total[1] += cpu
        return {file: tuple(v) for file, v in spent.items()}
    return {job.files[0].split("::")[0]: (job.elapsed_s, job.cpu_s)} if job.files else {}


def load_costs(repo):
    """{job name: (wall_s, cpu_s)}: the shipped table, then this checkout's own measurements."""
    costs = {}
    for path in (SHIPPED_COSTS, os.path.join(repo, ".ws", "suite_costs.json")):
        try:
            with open(path, encoding="utf-8") as f:
                costs.update({k: tuple(v) for k, v in json.load(f).items()})
        except (OSError, ValueError):
            pass
    return costs


def apply_costs(jobs, costs, cores):
    for job in jobs:
        wall, cpu = costs.get(job.name, (60.0, 30.0))
        job.wall_s = wall
        job.share = min(float(cores), job.fixed_share or max(0.05, cpu / max(wall, 1e-3)))


def remember_costs(repo, jobs):
    path = os.path.join(repo, ".ws", "suite_costs.json")
    costs = {}
    try:
        with open(path, encoding="utf-8") as f:
            costs = json.load(f)
    except (OSError, ValueError):
        pass
    costs.update({j.name: [round(j.elapsed_s, 1), round(j.cpu_s, 1)] for j in jobs if j.passed})
    with open(path, "w", encoding="utf-8") as f:
        f.write(costs_json(costs))


def costs_json(costs):
    """One job a line, as tools/suite/costs.json is kept (copy .ws/suite_costs.json there)."""
    lines = [f' "{name}": [{wall}, {cpu}]' for name, (wall, cpu) in sorted(costs.items())]
    return "{\n" + ",\n".join(lines) + "\n}\n"


def write(results, jobs, cores, wall_s, stress):
    """timing.md and timing.json in ``results``; returns the Markdown."""
    tiers = {}
    for job in sorted(jobs, key=lambda j: TIER_ORDER.index(j.tier)):
        t = tiers.setdefault(job.tier, {"jobs": 0, "wall_s": 0.0, "cpu_s": 0.0,
                                        "start": job.started, "end": job.ended})
        t["jobs"] += 1
        t["wall_s"] += job.elapsed_s
        t["cpu_s"] += job.cpu_s
        t["start"] = min(t["start"], job.started)
        t["end"] = max(t["end"], job.ended)
    per_file = {}
    for job in jobs:
        for file, (wall, cpu) in file_times(job, results).items():
            total = per_file.setdefault(file, [job.tier, 0.0, 0.0])
            total[1] += wall
            total[2] += cpu
    files = sorted(((f, t, w, c) for f, (t, w, c) in per_file.items()), key=lambda r: -r[2])
    cpu_s = sum(j.cpu_s for j in jobs)
    head = (f"{time.strftime('%Y-%m-%d %H:%M %Z')}, {os.cpu_count()} cores ({processor()}), "
            f"{cores} used; stress hog: {'yes' if stress else 'no'}")
    md = ["# Where the time went", "", head, "",
          f"Whole run: {wall_s:.0f} s wall, {cpu_s:.0f} s CPU in the jobs "
          f"({cpu_s / max(wall_s, 1e-3):.2f} cores busy on average).", "",
          "| tier | jobs | span s | jobs' wall s (summed) | CPU s |",
          "| --- | ---: | ---: | ---: | ---: |"]
    for tier, t in tiers.items():
        md.append(f"| {tier} | {t['jobs']} | {t['end'] - t['start']:.0f} | {t['wall_s']:.0f} "
                  f"| {t['cpu_s']:.0f} |")
    md += ["", f"The {min(SLOWEST, len(files))} slowest test files:", "",
           "| file | tier | wall s | CPU s |", "| --- | --- | ---: | ---: |"]
    md += [f"| {f} | {tier} | {w:.1f} | {c:.1f} |" for f, tier, w, c in files[:SLOWEST]]
    text = "\n".join(md) + "\n"
    with open(os.path.join(results, "timing.md"), "w", encoding="utf-8") as f:
        f.write(text)
    with open(os.path.join(results, "timing.json"), "w", encoding="utf-8") as f:
        json.dump({"wall_s": wall_s, "cpu_s": cpu_s, "cores": cores, "stress": stress,
                   "processor": processor(),
                   "tiers": {k: {"jobs": v["jobs"], "span_s": v["end"] - v["start"],
                                 "wall_s": v["wall_s"], "cpu_s": v["cpu_s"]}
                             for k, v in tiers.items()},
                   "jobs": {j.name: {"wall_s": j.elapsed_s, "cpu_s": j.cpu_s,
                                     "status": j.status} for j in jobs},
                   "files": [{"file": f, "tier": t, "wall_s": w, "cpu_s": c}
                             for f, t, w, c in files]}, f, indent=1)
    return text
