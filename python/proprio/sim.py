"""proprio.sim: the simulated world (MuJoCo, headless rendering) and the simulated robot.

    Scene(objects=[("mug", 0.3, 0.0)], width=640, height=480)
        .step(n), .render(camera="camera", mask=True, depth=False) -> dict of arrays,
        .camera() -> proprio.geometry.Camera, .object_pose(name), .set_arm_configuration(q)
    SimulatedRobot(TableOptions(objects=3, seed=1))
        the robot interface (proprio.robot): .look(), .push(start, end), .push_image(...);
        ground truth for scoring: .ground_truth(), .ground_truth_mask(), .scatter(seed)

Images are H x W x 3 uint8 in RGB order (converted from the library's BGR: a copy); masks
H x W uint16 object ids (0 background, 65535 the arm); depth H x W float32 metres. Every image is
a new array. A Scene or SimulatedRobot owns a GL context: use each from one thread; close() frees
it at once (it is also freed at interpreter exit, before the GL library goes).
"""

import atexit
import weakref

from . import _proprio

_s = _proprio.sim
TableOptions = _s.TableOptions
catalogue_names = _s.catalogue_names

_live = weakref.WeakSet()


@atexit.register
def _close_all():
    # GL contexts must go before the GL library's own exit handlers run.
    for obj in list(_live):
        obj.close()


class Scene(_s.Scene):
    __doc__ = _s.Scene.__doc__

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        _live.add(self)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


class SimulatedRobot(_s.SimulatedRobot):
    __doc__ = _s.SimulatedRobot.__doc__

    def __init__(self, options=None, objects=(), **table):
        """options: TableOptions (or its fields as keywords: objects count is `count`...);
        objects: catalogue names (else drawn by the seed)."""
        if options is None:
            options = TableOptions(**table)
        elif table:
            raise ValueError("pass TableOptions or its fields as keywords, not both")
        super().__init__(options, list(objects))
        _live.add(self)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


__all__ = ["Scene", "SimulatedRobot", "TableOptions", "catalogue_names"]
