#!/usr/bin/env python3
"""Times whole processes in shuffled rounds: each round runs every command once, in a new random
order, and the medians of wall, user and system seconds are printed per command. On a virtual
machine whose speed drifts, strict A-B alternation can favour one position; shuffling removes
that, and a second copy of a binary under another name is a control for what remains.

Usage: python3 tools/shuffled_timing.py ROUNDS NAME='COMMAND ...' [NAME='COMMAND ...' ...]
Example (quote each NAME=COMMAND as one argument):
  python3 tools/shuffled_timing.py 14 \\
    "a=./build/meso render scenes/default.toml -q -o /tmp/a.exr --overwrite" \\
    "b=/tmp/meso-copy render scenes/default.toml -q -o /tmp/b.exr --overwrite"
Commands are split on spaces (no shell); their output is discarded; a failing command stops the run.
"""
import random
import resource
import statistics
import subprocess
import sys
import time


def main(argv):
    if len(argv) < 3 or not argv[1].isdigit() or any("=" not in a for a in argv[2:]):
        sys.exit(__doc__)
    rounds = int(argv[1])
    commands = {}
    for arg in argv[2:]:
        name, command = arg.split("=", 1)
        if name in commands or not command.split():
            sys.exit(f"shuffled_timing: '{arg}': need a new NAME and a COMMAND")
        commands[name] = command.split()
    times = {name: [] for name in commands}
    rng = random.Random(1)
    for r in range(rounds):
        order = list(commands)
        rng.shuffle(order)
        for name in order:
            before = resource.getrusage(resource.RUSAGE_CHILDREN)
            start = time.monotonic()
            done = subprocess.run(commands[name], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            wall = time.monotonic() - start
            after = resource.getrusage(resource.RUSAGE_CHILDREN)
            if done.returncode != 0:
                sys.exit(f"shuffled_timing: {name} exited with {done.returncode}")
            times[name].append((wall, after.ru_utime - before.ru_utime, after.ru_stime - before.ru_stime))
        print(f"round {r + 1}/{rounds}", file=sys.stderr)
    for name, runs in times.items():
        wall, user, system = (statistics.median(run[k] for run in runs) for k in range(3))
        print(f"{name}: median wall {wall:.3f} s, user {user:.3f} s, sys {system:.3f} s ({len(runs)} runs)")


if __name__ == "__main__":
    main(sys.argv)
