#!/usr/bin/env python3
"""Runs a program and writes its stderr lines to LOG, each prefixed with "@ WALL CPU": the
seconds since the program started and the CPU seconds its threads have used by then
(/proc/PID/stat utime + stime). Every 0.2 s a line "@ WALL CPU" alone records the CPU clock
between progress lines too. eta_table.py --cpu reads such a log.

Why: on a machine shared with other people's builds the wall-clock rate of a run changes with
their load, which no ETA can foresee. Measured on the process's CPU clock instead, an ETA's
error is what the estimator itself gets wrong (what it would be on a machine whose load does
not change). Both are reported in README.md.

Usage: cpu_clock.py LOG PROGRAM [ARGS...]    (stdout passes through; exit status is PROGRAM's)
"""
import os
import subprocess
import sys
import threading
import time

TICK = os.sysconf("SC_CLK_TCK")


def cpu_seconds(pid):
    try:
        with open(f"/proc/{pid}/stat") as f:
            fields = f.read().rsplit(")", 1)[1].split()
        return (int(fields[11]) + int(fields[12])) / TICK  # utime, stime (fields 14, 15)
    except (OSError, IndexError, ValueError):
        return None


def main():
    log_path, cmd = sys.argv[1], sys.argv[2:]
    start = time.monotonic()
    proc = subprocess.Popen(cmd, stderr=subprocess.PIPE, text=True, bufsize=1)
    lock = threading.Lock()
    last_cpu = [0.0]
    with open(log_path, "w") as log:

        def stamp():
            cpu = cpu_seconds(proc.pid)
            if cpu is not None:
                last_cpu[0] = cpu
            return f"@ {time.monotonic() - start:.3f} {last_cpu[0]:.2f}"

        def sample():
            while proc.poll() is None:
                with lock:
                    log.write(stamp() + "\n")
                time.sleep(0.2)

        sampler = threading.Thread(target=sample, daemon=True)
        sampler.start()
        for line in proc.stderr:
            with lock:
                log.write(f"{stamp()} {line}")
                log.flush()
        rc = proc.wait()
        sampler.join()
    return rc


if __name__ == "__main__":
    sys.exit(main())
