"""One measured run of a study: the command's own CPU time (os.wait4 of its process, so several runs may go at
once in threads of one study), its wall time and peak memory. Shared by run.py and hydrostatic.py."""
import os
import subprocess
import time


def run_measured(cmd, log_path, cwd):
    """Runs cmd on one OpenMP thread (passive waiting) with stdout and stderr to log_path; returns
    (exit code, {"cpu_s", "wall_s", "max_rss_MB", "command"})."""
    t0 = time.monotonic()
    with open(log_path, "w") as log:
        p = subprocess.Popen(cmd, stdout=log, stderr=subprocess.STDOUT, cwd=cwd,
                             env={**os.environ, "OMP_NUM_THREADS": "1", "OMP_WAIT_POLICY": "passive"})
        _, status, usage = os.wait4(p.pid, 0)
    cost = {"cpu_s": usage.ru_utime + usage.ru_stime, "wall_s": time.monotonic() - t0,
            "max_rss_MB": usage.ru_maxrss / 1024.0, "command": " ".join(cmd)}
    return os.waitstatus_to_exitcode(status), cost
