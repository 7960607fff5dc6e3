"""A griffe extension for the Python API page (mkdocs.yml, scripts/docs): the package's
docstrings are plain text with doctest examples (`>>> ...` and the output below them), which
Markdown would read as nested quotes. Each such run of lines becomes a `pycon` code block."""

from __future__ import annotations

import griffe


def _fence_doctests(text: str) -> str:
    out: list[str] = []
    block = False
    for line in text.split("\n"):
        if line.lstrip().startswith(">>>") and not block:
            out.append("```pycon")
            block = True
        elif block and not line.strip():
            out.append("```")
            block = False
        out.append(line)
    if block:
        out.append("```")
    return "\n".join(out)


class DoctestBlocks(griffe.Extension):
    def on_package(self, *, pkg: griffe.Module, **kwargs) -> None:
        todo: list[griffe.Object] = [pkg]
        while todo:
            obj = todo.pop()
            if obj.docstring is not None and ">>>" in obj.docstring.value:
                obj.docstring.value = _fence_doctests(obj.docstring.value)
            todo.extend(m for m in obj.members.values() if not m.is_alias)
