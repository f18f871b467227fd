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
