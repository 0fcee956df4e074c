"""Shared by the benchmark scripts: print the measured figures and write them to JSON."""
import json


def report(figures, path):
    """Print ``figures`` (a flat dict) one per line and write them as JSON to ``path``."""
    for key, value in figures.items():
        print(f"{key:28s} {value}")
    path.write_text(json.dumps(figures, indent=2) + "\n")
    print(f"wrote {path}")
