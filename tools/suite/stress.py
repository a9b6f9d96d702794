"""``--stress``: a CPU hog on every core, at normal priority, for as long as the run lasts. A test
that passes only on an idle machine is measuring the machine, not the simulator."""
import multiprocessing
import os
import signal


def _spin():
    os.setpgrp()      # its own group: the runner's Ctrl-C reaches it only through stop()
    while True:
        pass


class Hog:
    def __init__(self, cores):
        self.cores = cores
        self.procs = []

    def __enter__(self):
        context = multiprocessing.get_context("fork")
        self.procs = [context.Process(target=_spin, daemon=True) for _ in range(self.cores)]
        for p in self.procs:
            p.start()
        return self

    def __exit__(self, *exc):
        for p in self.procs:
            try:
                os.kill(p.pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
            p.join()
