"""The stacking of an ensemble's members: every class's ``ensemble`` returns its members' run
dicts (the dict ``run`` returns) stacked along a leading member axis."""

import numpy as np


def stack(members, rows):
    """The dicts ``members`` (each a run's dict, or what a failed or interrupted member computed)
    stacked: every array gets a leading member axis and, along its first axis, ``rows`` entries
    for the states (one fewer for what is per step, as ``iterations``); a member's entries after
    its last state are NaN. Dicts of arrays (``q``, ``p`` by coordinate) are stacked key by key.
    """
    if not members:
        return {"t": np.empty((0, rows))}
    reached = [len(m["t"]) for m in members]
    return _stack(members, reached, rows)


def _stack(values, reached, rows):
    first = values[0]
    if isinstance(first, dict):
        return {key: _stack([v[key] for v in values], reached, rows) for key in first}
    arrays = [np.asarray(v) for v in values]
    # The states' arrays have a member's `len(t)` rows, the steps' one fewer: the same offset
    # for every member.
    length = rows + arrays[0].shape[0] - reached[0]
    out = np.full((len(arrays), length) + arrays[0].shape[1:], np.nan)
    for i, a in enumerate(arrays):
        out[i, : a.shape[0]] = a
    return out
