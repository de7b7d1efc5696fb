"""proprio.geometry: the pinhole Camera (K, R, t, P = K [R | t], OpenCV's frame; world = robot
base, metres). Its matrices are returned as new float64 arrays (copies)."""

from . import _proprio

Camera = _proprio.geometry.Camera

__all__ = ["Camera"]
