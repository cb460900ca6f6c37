source docs/results/gpu/issue10/stop31/env.sh
python3 docs/results/gpu/issue10/stop38/readset_check.py cuda_ad_rgb $S ${D//-D /} > /tmp/readset_check.log 2>&1
grep "frame inputs" /tmp/readset_check.log | tee $OUT/readset_check.txt; tail -n 3 /tmp/readset_check.log | cut -c1-300
