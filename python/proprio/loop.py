"""proprio.loop: look, plan, push. run_push(PushOptions(...), TableOptions(...),
PushPlanOptions(...)) is `proprio push`: a new simulated table, one planned push, scored by the
ground truth; it returns the push.json record as Python objects. The self-supervised loop is not
bound yet (it is being built in the library)."""

from . import _proprio

PushOptions = _proprio.loop.PushOptions
run_push = _proprio.loop.run_push

__all__ = ["PushOptions", "run_push"]
