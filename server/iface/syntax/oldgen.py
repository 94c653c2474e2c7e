"""File what a whole-file parse built with the garbage collector's oldest generation, in one step.

``compile`` pauses the cyclic garbage collector while it parses (a parse makes many
objects and frees none of them to the collector), so when it resumes, all the parse
built is in the youngest generation and the first young collection traverses every
object of the model: 5 ms at 10k lines, 37 ms at 50k (7×: the traversal's cache misses
grow with the heap). The model lives as long as its compilation, so it is moved to the
oldest generation at once instead (``gc.freeze()`` then ``gc.unfreeze()``: two list
splices, whatever the size), where only full collections look at it, as they would
after it survived two young collections.

CPython calls for a full collection when the objects that reached the oldest generation
by surviving collections are a quarter of what the last full collection left; objects
moved here are not counted there, so a model that became cyclic garbage could wait long
for one. The count is kept here instead: once ``ALLOWANCE`` objects were moved since the
last full collection, nothing more is moved until one has run, and the collector works as
it always does. Nothing is moved while some other code keeps objects frozen.
"""

from __future__ import annotations

import gc

#: Fewer young objects than this are left to the young collection (cheap at that size).
MIN_YOUNG = 20_000
#: The most objects moved between two full collections: a bound on the cyclic garbage kept waiting.
ALLOWANCE = 1_000_000

_moved = 0


def _on_collect(phase: str, info: dict[str, int]) -> None:
    """After a full collection nothing moved earlier is waiting any more."""
    global _moved
    if phase == "stop" and info["generation"] == 2:
        _moved = 0


gc.callbacks.append(_on_collect)


def file_as_old() -> int:
    """Move the youngest objects to the oldest generation when they are many; how many were moved."""
    global _moved
    young = gc.get_count()[0]
    if young < MIN_YOUNG or _moved + young > ALLOWANCE or gc.get_freeze_count():
        return 0
    gc.freeze()
    gc.unfreeze()
    _moved += young
    return young
