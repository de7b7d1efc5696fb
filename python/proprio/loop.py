"""proprio.loop: not bound yet (docs/python.md says what is). The loop library's calls take
the Options structs bound elsewhere in this package; their Python entry points are to come."""

__all__ = []
