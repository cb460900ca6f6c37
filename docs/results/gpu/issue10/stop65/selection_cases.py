"""Stop 65's A/B of the plan's host time: the stability catalog's two selection-time cases
("2 000 objects" and "20 000 objects": the median host ms of a frame's plan over frames 5-10,
llvm_ad_rgb) on the package of the checkout given, so that two trees can be run in turn:

    git worktree add /tmp/before <commit>
    for i in 1 2 3; do
        .venv/bin/python docs/results/gpu/issue10/stop65/selection_cases.py .
        .venv/bin/python docs/results/gpu/issue10/stop65/selection_cases.py /tmp/before
    done
"""
import sys

sys.path.insert(0, sys.argv[1])
import mitsuba as mi  # noqa: E402

mi.set_variant("llvm_ad_rgb")
import hybrid_integrator as hi  # noqa: E402
from hybrid_integrator.stability import catalog, run_case  # noqa: E402

hi.register()
figures = {c.name: round(run_case(c).figure, 3) for c in catalog() if c.name.endswith("objects: selection time")}
print(hi.__file__.rsplit("/hybrid_integrator", 1)[0], figures)
