#!/usr/bin/env bash
# Each CPU's speed for a pure-Python loop (best of 5 runs of 300k additions, ms), the process pinned
# to one CPU at a time with taskset, ROUNDS rounds in a row; then the same loop unpinned (issue 10, stop 58).
cat > /tmp/core_loop.py <<'PY'
import time
def f():
    s = 0
    for i in range(300000):
        s += i * i
    return s
best = 1e9
for _ in range(5):
    t = time.perf_counter(); f(); best = min(best, time.perf_counter() - t)
print(f"{best * 1e3:.1f}")
PY
for r in $(seq 1 ${ROUNDS:-10}); do
  echo -n "round $r ($(date +%T)):"; for c in $(seq 0 $(($(nproc) - 1))); do echo -n " $c:$(taskset -c $c python3 /tmp/core_loop.py)"; done; echo
done
echo -n "unpinned:"; for k in $(seq 1 16); do echo -n " $(python3 /tmp/core_loop.py)"; done; echo
