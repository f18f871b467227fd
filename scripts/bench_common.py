"""What the Python benchmark scripts share (scripts/bench-negatives.py, scripts/bench-conditions.py)."""
import json
import sys


def parse_sets(items):
    """--set section.key=value overrides as a nested config dict (values parsed as JSON when they
    are JSON: numbers, true/false, lists; otherwise kept as strings)."""
    config = {}
    for item in items:
        key, _, value = item.partition("=")
        if not value:
            sys.exit(f"--set {item!r}: expected section.key=value")
        try:
            parsed = json.loads(value)
        except json.JSONDecodeError:
            parsed = value
        node = config
        parts = key.split(".")
        for part in parts[:-1]:
            node = node.setdefault(part, {})
        node[parts[-1]] = parsed
    return config


def pose_off_by(T, degrees, metres, rng):
    """T moved by `degrees` about a random axis and `metres` along a random direction, both drawn
    from rng and applied in T's source frame (T @ offset): a motion prior with that error."""
    import numpy as np

    axis = rng.normal(size=3)
    axis /= np.linalg.norm(axis)
    direction = rng.normal(size=3)
    direction /= np.linalg.norm(direction)
    a = np.radians(degrees)
    K = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    offset = np.eye(4)
    offset[:3, :3] = np.eye(3) + np.sin(a) * K + (1 - np.cos(a)) * K @ K
    offset[:3, 3] = metres * direction
    return T @ offset
