"""proprio: a robot arm that learns the objects on a table by pushing them.

The Python face of proprio's C++ library (docs/python.md). One submodule per library module:

    proprio.core          version, data directory
    proprio.topics        online LDA and the Mixture of Topics as scikit-learn estimators,
                          the Dirichlet fit, corpora (scipy.sparse CSR in)
    proprio.features      visual vocabularies: build, quantize
    proprio.episode       recorded interactions read as numpy arrays
    proprio.segmentation  Motion-Likelihood segmentation of an episode (maps and masks)
    proprio.geometry      camera matrices
    proprio.sim           the simulated world: scenes, rendering, the simulated robot
    proprio.robot         the robot interface (look, push) on the simulated robot
    proprio.recognition, proprio.planning, proprio.loop   what is bound of them so far

Errors: a file that cannot be opened raises OSError (FileNotFoundError when missing); bad content
or arguments raise ValueError with the CLI's one-line message ("FILE:LINE: problem").
"""

import os as _os

# In the build tree (build/python/proprio) the shipped data is build/share/proprio; an installed
# package finds <prefix>/share/proprio through the library itself.
if not _os.environ.get("PROPRIO_DATA_DIR"):
    _here = _os.path.dirname(_os.path.abspath(__file__))
    _build_data = _os.path.join(_here, "..", "..", "share", "proprio")
    if _os.path.isdir(_os.path.join(_build_data, "models")):
        _os.environ["PROPRIO_DATA_DIR"] = _os.path.normpath(_build_data)

from . import _proprio  # noqa: E402
from . import core  # noqa: E402
from . import topics  # noqa: E402

__version__ = _proprio.core.__version__

__all__ = ["core", "topics", "features", "episode", "segmentation", "geometry", "sim", "robot",
           "recognition", "planning", "loop", "__version__"]


def __getattr__(name):
    # The vision and robot modules load OpenCV and MuJoCo state lazily: `import proprio` stays
    # cheap for a topic-model user.
    if name in __all__:
        import importlib
        module = importlib.import_module("." + name, __name__)
        globals()[name] = module
        return module
    raise AttributeError(f"module 'proprio' has no attribute {name!r}")
