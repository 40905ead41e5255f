"""Text read from a file (a cube's attributes and names, a path) made safe to print on a terminal.

A cube is data, and its attribute strings can hold anything: an escape sequence that retitles the
terminal or hides what follows (OSC, CSI), a carriage return that overwrites the line before it, a
bidirectional override that reorders it. `escape` writes every such character as a Python-style escape
(\\x1b, \\r, \\u202e), so what is printed is what the file holds, and nothing the terminal would act on.
"""

from __future__ import annotations

import unicodedata

#: Unicode categories a terminal acts on or shows as nothing: controls (C0, DEL, C1), format characters
#: (bidirectional overrides, zero-width), line and paragraph separators, surrogates (undecodable bytes of
#: a file name), private use and unassigned code points
_HIDDEN = frozenset({"Cc", "Cf", "Zl", "Zp", "Cs", "Co", "Cn"})


def escape(text: object) -> str:
    """`text` as str with every control, format or separator character written as its escape."""
    text = str(text)
    if text.isprintable():  # the common case: nothing to do (isprintable is false for all of _HIDDEN)
        return text
    return "".join(_escaped(c) if unicodedata.category(c) in _HIDDEN else c for c in text)


def _escaped(c: str) -> str:
    n = ord(c)
    if n < 0x100:
        return f"\\x{n:02x}"
    return f"\\u{n:04x}" if n < 0x10000 else f"\\U{n:08x}"
