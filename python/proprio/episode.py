"""proprio.episode: recorded interactions (docs/formats/episode.md) read as numpy arrays.

    e = Episode.read("episodes/push_000")
    e.frame(i)    H x W x 3 uint8 RGB (decoded and converted from BGR: a new array)
    e.frames()    N x H x W x 3 uint8, all frames (decoded straight into one array)
    e.mask(i)     H x W uint16 ground-truth object ids; e.depth(i) H x W uint16 mm
    e.arm()       dict: t (N,), q (N x 5) rad, ee (N x 3) m, touching (N,) bool
    e.camera      proprio.geometry.Camera; e.first_touch_frame; e.objects

Reading a directory that does not exist raises FileNotFoundError; a bad file ValueError naming it.
"""

from . import _proprio

Episode = _proprio.episode.Episode


def read_episode(path) -> Episode:
    """Reads and validates an episode directory."""
    return Episode.read(path)


__all__ = ["Episode", "read_episode"]
