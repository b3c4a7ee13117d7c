"""A pickled object that runs code when loaded: the planted payload of the checkpoint-safety tests."""

from __future__ import annotations

from pathlib import Path


class PlantedCode:
    """Unpickling this creates `marker`; a loader that unpickles anything leaves the file behind."""

    def __init__(self, marker: Path) -> None:
        self.marker = str(marker)

    def __reduce__(self):
        return (open, (self.marker, "w"))
