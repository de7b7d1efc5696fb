"""proprio.core: version, the data directory, and how errors reach Python.

Errors: the library's proprio::Error becomes ValueError with the CLI's one-line message, except
that a file that cannot be opened becomes OSError (FileNotFoundError when it does not exist).
A broken internal invariant becomes RuntimeError.
"""

from . import _proprio

__version__: str = _proprio.core.__version__
git_commit: str = _proprio.core.git_commit


def data_directory() -> str:
    """The directory of proprio's shipped data (models/, objects/, scenarios/)."""
    return _proprio.core.data_directory()


__all__ = ["__version__", "git_commit", "data_directory"]
