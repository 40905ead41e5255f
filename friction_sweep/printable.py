"""Text read from a file (a cube's attributes and names, a path) made safe to print on a terminal, and the
one rule for the characters a file name fsweep writes or records may hold.

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


#: Unicode categories refused in names: controls (C0, DEL, C1 such as NEL), format characters
#: (bidirectional overrides, zero-width ones), line and paragraph separators (U+2028, U+2029)
_CONTROL_CATEGORIES = ("Cc", "Cf", "Zl", "Zp")


def name_problem(text: str) -> str | None:
    """What makes `text` no name fsweep writes or records (None: nothing), as the end of a sentence whose
    subject is the name: bytes that are not UTF-8 (a surrogate, as Python decodes them), a control, format
    or separator character, a private-use character (U+E000..U+F8FF, planes 15 and 16: it means what some
    program chose), a noncharacter (U+FDD0..U+FDEF, U+xFFFE, U+xFFFF) or an unassigned code point: none is
    text another program shows for sure as the same name. The one rule for every name fsweep checks."""
    try:
        text.encode("utf-8")
    except UnicodeEncodeError:
        return "is not valid UTF-8 (undecodable bytes, or a lone surrogate)"
    for ch in text:
        category, n = unicodedata.category(ch), ord(ch)
        if category in _CONTROL_CATEGORIES:
            return f"holds a control character (U+{n:04X}, {unicodedata.name(ch, 'a control')})"
        if category == "Co":
            return f"holds a private-use character (U+{n:04X})"
        if category == "Cn":
            what = "a noncharacter" if 0xFDD0 <= n <= 0xFDEF or n & 0xFFFE == 0xFFFE else "an unassigned code point"
            return f"holds {what} (U+{n:04X})"
    return None
