"""Stop 66: the LLVM IR of every kernel of two hybrid frames (the first records and compiles) of a
bench scene at 320×180 on ``llvm_ad_rgb``, printed by Dr.Jit (``dr.JitFlag.PrintIR``), to compare
the forms a kernel takes from one process to the next. Run it in several processes, then cut one
kernel out of each output and diff them, e.g. for the dining room's trace kernel:

    for i in 1 2 3 4 5 6; do .venv/bin/python docs/results/gpu/issue10/stop66/kernel_ir.py \
      scenes/dining_room.xml dining_dir=../shared/scenes/dining-room > /tmp/ir$i.txt 2>&1; done
    grep -o 'drjit_[0-9a-f]*' /tmp/ir*.txt | sort -u | grep -E '0b686f51|bf225b10'
    awk '/define void @drjit_(0b686f51|bf225b10)/,/^}/' /tmp/irK.txt | sed -E 's/drjit_[0-9a-f]+/drjit_X/g'
"""
import sys

import drjit as dr
import mitsuba as mi

mi.set_variant("llvm_ad_rgb")
import hybrid_integrator as hi  # noqa: E402
from hybrid_integrator.bench import load_bench_scene  # noqa: E402
from hybrid_integrator.raster.camera import sensor_to_world  # noqa: E402

scene, _ = load_bench_scene(sys.argv[1], {"resx": "320", "resy": "180", **dict(d.split("=", 1) for d in sys.argv[2:])})
camera = sensor_to_world(scene.sensors()[0])
dr.set_flag(dr.JitFlag.PrintIR, True)
dr.set_log_level(dr.LogLevel.Info)
hi.render_sequence(scene, [camera] * 2, spp=1, layers=False)
