"""A figure of the library (SVG), as every result object hands it out."""

from __future__ import annotations


class Figure:
    """A figure: its ``name``, ``caption`` and SVG text; displays itself in Jupyter."""

    def __init__(self, name: str, caption: str, svg: str):
        self.name, self.caption, self.svg = name, caption, svg

    def _repr_svg_(self) -> str:
        return self.svg

    def save(self, path: str) -> None:
        """Writes the SVG to ``path``."""
        with open(path, "w", encoding="utf-8") as f:
            f.write(self.svg)

    def __repr__(self) -> str:
        return f"Figure({self.name!r}: {self.caption})"
