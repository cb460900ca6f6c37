#!/usr/bin/env bash
# Stop 31, last GPU run: this stop's code (= stop 30's) once more on whatever host the lent H200
# comes with (the hosts' speed differed between this stop's machine starts: path_profile/), with a
# fixed host-speed probe first and last. One H200, cuda_ad_rgb, 1280x720. Needs extras.sh first.
source docs/results/gpu/issue10/stop31/env.sh
R=/tmp/f; mkdir -p $R
host() { python3 -c "import time, statistics as s
def t():
    a = time.perf_counter(); sum(range(2_000_000)); return (time.perf_counter() - a) * 1e3
print('host probe: sum(range(2e6)) median of 15: %.2f ms' % s.median(t() for _ in range(15)))"; }
host | tee $R/host.txt
python3 scripts/budget_benchmark.py --variant cuda_ad_rgb --frames 50 --resx 1280 --resy 720 --importance 0.01 -o $R/budget > $R/budget.log 2>&1
grep "^|" $R/budget.md | sed -n '3,7p'
python3 -m hybrid_integrator.cli bench --variant cuda_ad_rgb --frames 20 --no-accuracy --max-path-spp 1 $S --budgets 0.5 $D -o $R/bench > $R/bench.log 2>&1
grep -A7 "^| scene" $R/bench/bench.md | tail -5 | cut -d'|' -f2,6-12; grep -E "^\| (hybrid@50%|rt-baseline)" $R/bench/bench.md | cut -d'|' -f2,3
python3 -m hybrid_integrator.cli bench --variant cuda_ad_rgb --frames 20 --no-accuracy --max-path-spp 1 ${S% scenes/many_objects.xml} --budgets --effects "shadow, reflection, refraction" $D -o $R/bench_paper > $R/bench_paper.log 2>&1
grep -A6 "^| scene" $R/bench_paper/bench.md | tail -4 | cut -d'|' -f2,6-12
python3 scripts/trace_overhead.py --variant cuda_ad_rgb --resx 1280 --resy 720 --repeats 21 -o $R/trace_overhead > $R/trace.log 2>&1
grep -A12 '"fit"' $R/trace.log | head -14; grep "^measured" $R/trace.log | cut -c1-200
host | tee -a $R/host.txt
tar -cJf $OUT/f.tar.xz -C /tmp f
