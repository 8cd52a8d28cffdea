#!/usr/bin/env python3
"""Time a command against another in pairs, as the speed figures of Documentation~/benchmarks.md are measured: A and B
run in turn (A B A B ...), each a whole process, and the ratio A/B is taken pair by pair, so a machine whose speed
drifts (other jobs, thermal limits) moves both runs of a pair alike.

  python3 Tools~/experiments/paired-time.py -n 3 --warmup 1 [--timeout S] --vs "COMMAND_B" -- COMMAND_A [ARG ...]
  python3 Tools~/experiments/paired-time.py -n 3 --warmup 1 -- COMMAND_A [ARG ...]     # A alone: its runs and medians

COMMAND_A runs as given (no shell); COMMAND_B is one string split as a shell splits words (shlex). Prints every run
(wall s, CPU s = user + system of the process and its children, peak resident MB), then the medians of A and B and the
pair ratios A/B of wall and CPU time (median, min-max). Standard library only: wall time from time.perf_counter, CPU
time and peak memory from the children's resource usage. Exit code 1 when a run fails (its output is shown).
"""

from __future__ import annotations

import argparse
import resource
import shlex
import statistics
import subprocess
import sys
import time
from dataclasses import dataclass
from typing import Callable


@dataclass(frozen=True)
class Run:
    wall: float
    cpu: float
    peak_mb: float


def timed(command: list[str], timeout: float | None = None) -> Run:
    """One whole process: its wall time, its (and its children's) CPU time and its peak resident memory; a run longer
    than `timeout` seconds is killed and fails the call."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    try:
        done = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, check=False, timeout=timeout)
    except subprocess.TimeoutExpired:
        raise SystemExit(f"paired-time: {shlex.join(command)} ran longer than --timeout {timeout:g} s") from None
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if done.returncode != 0:
        sys.stdout.write(done.stdout.decode(errors="replace"))
        raise SystemExit(f"paired-time: {shlex.join(command)} exited with {done.returncode}")
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    # ru_maxrss of the children is the largest of any child so far (kB on Linux): a lower bound for later runs only
    # when an earlier one was larger, so it is reported as the running maximum it is.
    return Run(wall=wall, cpu=cpu, peak_mb=after.ru_maxrss / 1024.0)


def spread(values: list[float]) -> str:
    return f"{statistics.median(values):.3f} ({min(values):.3f}-{max(values):.3f})"


def alone(command: list[str], count: int, warmup: int, run: Callable[[list[str]], Run]) -> int:
    """Without a baseline: `warmup` uncounted runs, then `count` counted ones and their medians."""
    for _ in range(warmup):
        run(command)
    runs = []
    print("run | wall s | CPU s | peak MB so far")
    for number in range(1, count + 1):
        runs.append(run(command))
        print(f"{number} | {runs[-1].wall:.3f} | {runs[-1].cpu:.3f} | {runs[-1].peak_mb:.0f}", flush=True)
    print(f"median wall s {spread([r.wall for r in runs])}, median CPU s {spread([r.cpu for r in runs])}")
    return 0


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("-n", type=int, default=3, help="counted pairs (default 3)")
    parser.add_argument("--warmup", type=int, default=1, help="uncounted pairs first (default 1)")
    parser.add_argument("--timeout", type=float, default=None, help="seconds a run may take (default: no limit)")
    parser.add_argument("--vs", default=None,
                        help="command B (the baseline), one string split as a shell does; without it A alone is timed")
    parser.add_argument("command", nargs=argparse.REMAINDER, help="-- COMMAND_A [ARG ...]")
    args = parser.parse_args(argv)
    command_a = args.command[1:] if args.command[:1] == ["--"] else args.command
    command_b = shlex.split(args.vs) if args.vs is not None else None
    if not command_a or command_b == []:
        parser.error("give the commands: [--vs 'COMMAND_B'] -- COMMAND_A [ARG ...]")
    if args.n < 1 or args.warmup < 0:
        parser.error(f"-n {args.n} must be >= 1 and --warmup {args.warmup} >= 0")
    if args.timeout is not None and not args.timeout > 0:
        parser.error(f"--timeout {args.timeout} must be > 0 seconds")

    def run(command: list[str]) -> Run:
        return timed(command, args.timeout)

    if command_b is None:
        return alone(command_a, args.n, args.warmup, run)
    for _ in range(args.warmup):
        run(command_a)
        run(command_b)
    pairs: list[tuple[Run, Run]] = []
    print("pair | A wall s | A CPU s | B wall s | B CPU s | A/B wall | A/B CPU | peak MB so far")
    for number in range(1, args.n + 1):
        a, b = run(command_a), run(command_b)
        pairs.append((a, b))
        print(f"{number} | {a.wall:.3f} | {a.cpu:.3f} | {b.wall:.3f} | {b.cpu:.3f} | {a.wall / b.wall:.3f} | "
              f"{a.cpu / b.cpu if b.cpu > 0 else float('nan'):.3f} | {max(a.peak_mb, b.peak_mb):.0f}", flush=True)
    print(f"A median wall s {statistics.median([a.wall for a, _ in pairs]):.3f}, "
          f"B median wall s {statistics.median([b.wall for _, b in pairs]):.3f}")
    print(f"A/B wall {spread([a.wall / b.wall for a, b in pairs])}")
    cpu_ratios = [a.cpu / b.cpu for a, b in pairs if b.cpu > 0]
    print(f"A/B CPU {spread(cpu_ratios) if cpu_ratios else 'n/a (B used no measurable CPU)'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
