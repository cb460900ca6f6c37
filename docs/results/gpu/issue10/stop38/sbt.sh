source docs/results/gpu/issue10/stop31/env.sh
python3 docs/results/gpu/issue10/stop38/probe.py --variant cuda_ad_rgb --resx 1280 --resy 720 --skip-compaction --log /tmp/rec.log > /tmp/p.out 2>&1
tail -n 3 /tmp/p.out
grep -n -i "sbt\|pipeline" /tmp/rec.log | grep -v "jit_optix_log\|^\s*$" | head -40
grep -c "" /tmp/rec.log
xz -c /tmp/rec.log > $OUT/rec.log.xz
