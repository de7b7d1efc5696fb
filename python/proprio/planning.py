"""proprio.planning: the push planner's options (thesis 7.2.1); the planner runs inside
proprio.loop.run_push. Planning on a look of your own is not bound yet."""

from . import _proprio

PushPlanOptions = _proprio.planning.PushPlanOptions

__all__ = ["PushPlanOptions"]
