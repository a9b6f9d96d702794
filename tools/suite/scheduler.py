"""Runs the jobs side by side within the machine's cores.

Each job keeps ``share`` cores busy on average (its CPU time over its wall time, remembered
from earlier runs); jobs start, longest first, while the shares of the running ones fit in the
cores times OVERCOMMIT (most of a ROS test's time is waiting on simulated time and topics, so a
little more than the cores keeps them busy). A job that asks for the machine to itself starts
when nothing else runs, and nothing starts beside it. A job running past HANG_S is stopped and
fails: the run ends instead of hanging."""
import re
import time

from suite import jobs as jobs_module

OVERCOMMIT = 1.25
HANG_S = 1800.0
POLL_S = 0.2
RESULT_LINE = re.compile(r"^ \* (RESULT|TESTS|ERRORS|FAILURES)")


def report(job, say):
    verdict = "passed" if job.passed else ("HUNG, stopped" if job.status == "hung" else
                                           f"FAILED (exit status {job.status})")
    say(f"-- {job.name}: {verdict} ({job.elapsed_s:.0f} s wall, {job.cpu_s:.0f} s CPU)")
    if job.tier == "rostest":
        lines = [line for line in job.tail(60).splitlines() if RESULT_LINE.match(line)]
        if lines:
            say("  " + " ".join(line.strip() for line in lines))
    if not job.passed:
        say(job.tail(40))


def run(jobs, cwd, cores, say=print):
    """Run every job; return them in the order they ended."""
    budget = cores * OVERCOMMIT
    pending = sorted(jobs, key=lambda j: (j.alone, -j.wall_s))
    running, ended = [], []
    try:
        while pending or running:
            for job in list(pending):
                busy = sum(j.share for j in running)
                alone_running = any(j.alone for j in running)
                if job.alone:
                    fits = not running
                else:
                    fits = not alone_running and (not running or busy + job.share <= budget)
                if fits:
                    pending.remove(job)
                    job.start(cwd)
                    running.append(job)
                elif job.alone:
                    break     # keep its place: nothing else jumps ahead of a waiting alone job
            time.sleep(POLL_S)
            for job in list(running):
                if not job.poll() and job.elapsed_s > HANG_S:
                    job.stop()
                    job.status = "hung"
                if job.status is not None:
                    running.remove(job)
                    ended.append(job)
                    report(job, say)
    except BaseException:
        for job in running:
            job.stop()
        raise
    finally:
        time.sleep(POLL_S)        # a process killed with its group is gone a moment later
        jobs_module.sweep_accounts()
    return ended
