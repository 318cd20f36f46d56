"""A study's figure: the SVG text the ``pkm`` command writes under the same name, shown inline
by Jupyter (``_repr_svg_``) and written to a file by :meth:`Figure.save`."""

import os
from typing import Union


class Figure:
    """An SVG figure of a study (a chart or the robot drawing)."""

    __slots__ = ("name", "svg")

    def __init__(self, name: str, svg: str) -> None:
        self.name = name
        self.svg = svg

    def _repr_svg_(self) -> str:
        return self.svg

    def save(self, path: Union[str, "os.PathLike[str]"]) -> None:
        """Writes the SVG text to ``path`` (UTF-8)."""
        with open(path, "w", encoding="utf-8") as f:
            f.write(self.svg)

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Figure) and (self.name, self.svg) == (other.name, other.svg)

    def __hash__(self) -> int:
        return hash((self.name, self.svg))

    def __repr__(self) -> str:
        return f"Figure({self.name!r}, {len(self.svg)} characters of SVG)"

    def __getstate__(self) -> "tuple[str, str]":
        return (self.name, self.svg)

    def __setstate__(self, state: "tuple[str, str]") -> None:
        self.name, self.svg = state
