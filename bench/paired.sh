#!/bin/bash
# Paired cpu-time comparison of two commands on a shared machine: runs A and B alternately N times
# (A B A B ...), takes each run's user + system cpu time of the child process (getrusage via
# os.wait4), and prints min/median/max per command and the median (min-max) of the pairwise ratios
# A/B, with the load average before and after. With one command, its N runs only.
#   bash bench/paired.sh [-n N] -- 'command A' ['command B']
# Commands run through bash -c, their output discarded.
set -euo pipefail
n=5
while [ $# -gt 0 ]; do
  case "$1" in
    -n) n=$2; shift 2 ;;
    --) shift; break ;;
    *) break ;;
  esac
done
if [ $# -lt 1 ] || [ $# -gt 2 ]; then
  echo "usage: bash bench/paired.sh [-n N] -- 'command A' ['command B']" >&2
  exit 2
fi
exec /usr/bin/python3 - "$n" "$@" <<'PY'
import os, statistics, subprocess, sys
n, cmds = int(sys.argv[1]), sys.argv[2:]
if n < 1:
    sys.exit("paired.sh: -n must be at least 1")

def cpu(cmd):
    p = subprocess.Popen(["bash", "-c", cmd], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    _, status, ru = os.wait4(p.pid, 0)
    code = os.waitstatus_to_exitcode(status)
    if code != 0:
        sys.exit(f"paired.sh: command failed (exit {code}): {cmd}")
    return ru.ru_utime + ru.ru_stime

load0 = os.getloadavg()[0]
names = "AB"[:len(cmds)]
t = [[] for _ in cmds]
for i in range(n):
    for k in range(len(cmds)):
        t[k].append(cpu(cmds[k]))
    runs = "  ".join(f"{names[k]} {t[k][-1]:.3f} s" for k in range(len(cmds)))
    print(f"round {i + 1}: {runs}" + (f"  A/B {t[0][-1] / t[1][-1]:.4f}" if len(cmds) == 2 else ""), flush=True)
for k, name in enumerate(names):
    v = t[k]
    print(f"{name}: cpu s min {min(v):.3f} median {statistics.median(v):.3f} max {max(v):.3f}  ({cmds[k]})")
if len(cmds) == 1:
    print(f"load average {load0:.2f} -> {os.getloadavg()[0]:.2f}")
    sys.exit(0)
r = [a / b for a, b in zip(t[0], t[1])]
print(f"A/B: median {statistics.median(r):.4f} (min {min(r):.4f}, max {max(r):.4f}) over {n} pairs; "
      f"load average {load0:.2f} -> {os.getloadavg()[0]:.2f}")
PY
