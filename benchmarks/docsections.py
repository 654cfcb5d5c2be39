"""docs/performance.md is written by five scripts: run.py (the head), scaling.py (from
``<!-- scaling -->``), scale.py (from ``<!-- scale -->``), sweep_hook.py (from
``<!-- sweeps -->``) and battery.py (from ``<!-- battery -->``); each replaces only its part."""
from __future__ import annotations

from pathlib import Path

MARKERS = ["<!-- head -->", "<!-- scaling -->", "<!-- scale -->", "<!-- sweeps -->", "<!-- battery -->"]


def write_section(path: Path, marker: str, text: str) -> None:
    old = path.read_text() if path.exists() else ""
    parts = {}
    if old and not old.startswith(MARKERS[0]):
        old = MARKERS[0] + "\n" + old
    for i, m in enumerate(MARKERS):
        a = old.find(m)
        if a < 0:
            continue
        ends = [old.find(n) for n in MARKERS[i + 1:] if old.find(n) > a]
        parts[m] = old[a + len(m):min(ends) if ends else len(old)].strip("\n")
    parts[marker] = text.strip("\n")
    path.write_text("\n\n".join(f"{m}\n{parts[m]}" for m in MARKERS if m in parts) + "\n")
