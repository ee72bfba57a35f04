# SPDX-License-Identifier: Apache-2.0
"""The fenced code blocks of docs/python.md, for the tests that run them (docs are code)."""
import pathlib
import re

DOC = pathlib.Path(__file__).resolve().parents[2] / "docs" / "python.md"


def blocks(lang):
    """(line, code) of every ```lang block of docs/python.md."""
    out, body, start, inside = [], [], 0, None
    for n, line in enumerate(DOC.read_text(encoding="utf-8").splitlines(), 1):
        m = re.match(r"^```(\S*)", line)
        if m and inside is None:
            inside, start, body = m.group(1), n, []
        elif line.startswith("```") and inside is not None:
            if inside == lang:
                out.append((start, "\n".join(body) + "\n"))
            inside = None
        elif inside is not None:
            body.append(line)
    return out


def python_blocks(vcan):
    """The python blocks that need vcan0 (vcan=True) or not."""
    return [(n, code) for n, code in blocks("python") if ("vcan0" in code) == vcan]
