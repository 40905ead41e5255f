"""Read spec YAML into plain Python values, remembering where each key and value sits."""

from __future__ import annotations

import os
import re
import stat
from dataclasses import dataclass, field
from typing import Any

from ruamel.yaml import YAML
from ruamel.yaml.constructor import ConstructorError, DuplicateKeyError, RoundTripConstructor
from ruamel.yaml.error import MarkedYAMLError, YAMLError
from ruamel.yaml.nodes import MappingNode, ScalarNode, SequenceNode

from .base import show
from .errors import SpecError

KeyPath = tuple[str | int, ...]
Position = tuple[int, int]

#: a spec is a few dozen values; these bounds keep a small hostile file from costing time or memory:
#: values repeated through YAML aliases (an "alias bomb" of a few hundred bytes expands to 10^9) ...
MAX_ALIAS_VALUES = 10_000
#: ... and nesting (a spec nests 4 deep; deep nesting exhausts the parser's recursion) ...
MAX_DEPTH = 32
#: ... and size (parsing takes about 20 s a megabyte; 1000 time-history points take 20 kB)
MAX_SPEC_BYTES = 256 * 1024


@dataclass
class Document:
    """Plain data of one YAML file plus 1-based (line, column) of keys and values by key path."""

    data: Any
    source: str
    value_pos: dict[KeyPath, Position] = field(default_factory=dict)
    key_pos: dict[KeyPath, Position] = field(default_factory=dict)
    # Block collections and empty values: ruamel places the value at the next token, so use the key.
    at_key: set[KeyPath] = field(default_factory=set)
    # values produced by repeating an aliased collection (bounded by MAX_ALIAS_VALUES)
    alias_values: int = 0

    def locate(self, path: KeyPath, *, key: bool = False) -> tuple[int | None, int | None]:
        """Where to point for a problem at `path`; falls back to the nearest located ancestor."""
        if path in self.value_pos or path in self.key_pos:
            if (key or path in self.at_key) and path in self.key_pos:
                return self.key_pos[path]
            return self.value_pos.get(path) or self.key_pos[path]
        for n in range(len(path) - 1, 0, -1):
            anc = path[:n]
            if anc in self.key_pos:
                return self.key_pos[anc]
            if anc in self.value_pos:
                return self.value_pos[anc]
        return (None, None)


def read_text(path: str | os.PathLike[str]) -> str:
    """The file's text, or SpecError if it cannot be read as UTF-8 (or is not a regular file of at
    most MAX_SPEC_BYTES: a FIFO would wait forever, /dev/zero would fill the memory)."""
    source = os.fspath(path)
    try:
        st = os.stat(source)
        if stat.S_ISDIR(st.st_mode):
            raise IsADirectoryError
        if not stat.S_ISREG(st.st_mode):
            raise SpecError.single(source, "is not a regular file (a FIFO, a device?): give a spec file")
        if st.st_size > MAX_SPEC_BYTES:
            raise SpecError.single(source, _too_large(st.st_size))
        with open(source, encoding="utf-8") as fh:
            return fh.read(MAX_SPEC_BYTES + 1)
    except FileNotFoundError:
        raise SpecError.single(source, "file not found") from None
    except IsADirectoryError:
        raise SpecError.single(source, "is a directory, not a spec file") from None
    except UnicodeDecodeError as e:
        raise SpecError.single(source, f"not UTF-8 text ({e.reason} at byte {e.start})") from None
    except OSError as e:
        raise SpecError.single(source, f"cannot read file: {e.strerror or e}") from None
    except ValueError:  # a NUL in the path (os.stat's "embedded null byte")
        raise SpecError.single(source.replace("\0", "\\0"), "a path holding a NUL character names no file") from None


#: YAML's own tags, as a spec writes them
_YAML_TAG = "tag:yaml.org,2002:"


def short_tag(tag: str) -> str:
    """tag:yaml.org,2002:float -> !!float."""
    return "!!" + tag.removeprefix(_YAML_TAG) if tag.startswith(_YAML_TAG) else tag


class _LocatedConstructor(RoundTripConstructor):
    """A value its tag cannot hold (`!!float "abc"`, `!!bool maybe`) is an error at its line and column:
    ruamel raises a bare ValueError or KeyError without a position."""

    def construct_non_recursive_object(self, node: Any, tag: str | None = None) -> Any:
        try:
            return super().construct_non_recursive_object(node, tag)
        except (YAMLError, RecursionError):
            raise
        except Exception:
            value = node.value if isinstance(node, ScalarNode) else "..."
            raise ConstructorError(None, None, f"{short_tag(str(node.tag))} cannot hold {show(value)}",
                                   node.start_mark) from None


def _too_large(size: int) -> str:
    return f"is {size} bytes; a spec is at most {MAX_SPEC_BYTES} (long grids are written {{start, stop, num}} or " \
        "{start, stop, step})"


def parse_yaml(text: str, source: str) -> Document:
    """Parse one YAML document (YAML 1.2, duplicate keys rejected) of at most MAX_SPEC_BYTES into a Document."""
    size = len(text.encode("utf-8", "surrogatepass")) if len(text) * 4 > MAX_SPEC_BYTES else len(text)
    if size > MAX_SPEC_BYTES:
        raise SpecError.single(source, _too_large(size))
    yaml = YAML(typ="rt")
    yaml.Constructor = _LocatedConstructor
    try:
        # ruamel constructs a recursive alias as null, silently: find it in the node graph first
        _refuse_recursion(YAML(typ="rt").compose(text), source)
        tree = yaml.load(text)
    except DuplicateKeyError as e:
        raise _duplicate_key_error(e, text, source) from None
    except MarkedYAMLError as e:
        raise _marked_error(e, source) from None
    except (YAMLError, ValueError, TypeError) as e:
        # e.g. `!!float abc` raises a bare ValueError with no position
        raise SpecError.single(source, f"invalid YAML: {' '.join(str(e).split())}") from None
    except RecursionError:
        raise SpecError.single(source, f"invalid YAML: nested deeper than the parser can follow "
                               f"(a spec nests at most {MAX_DEPTH} levels)") from None
    doc = Document(data=None, source=source)
    doc.data = _plain(tree, (), doc, set(), False)
    return doc


def _refuse_recursion(root: Any, source: str) -> None:
    """SpecError if a collection contains itself through an alias (depth-first, each node once)."""
    active: set[int] = set()
    done: set[int] = set()
    # iterative: (node, entering); a deep file is refused by the parser before it gets here
    stack: list[tuple[Any, bool]] = [(root, True)] if root is not None else []
    while stack:
        node, entering = stack.pop()
        if not entering:
            active.discard(id(node))
            continue
        if id(node) in active:
            mark = node.start_mark
            raise SpecError.single(source, f"recursive YAML alias: the value anchored at line {mark.line + 1} "
                                   "contains itself", line=mark.line + 1, column=mark.column + 1)
        if id(node) in done or not isinstance(node, (MappingNode, SequenceNode)):
            continue
        done.add(id(node))
        active.add(id(node))
        stack.append((node, False))
        children = [c for pair in node.value for c in pair] if isinstance(node, MappingNode) else node.value
        stack.extend((child, True) for child in reversed(children))


def _marked_error(e: MarkedYAMLError, source: str) -> SpecError:
    mark = e.problem_mark or e.context_mark
    reason = f"invalid YAML: {e.problem or e.context or 'syntax error'}"
    if e.context and e.problem and e.context_mark is not None:
        cm = e.context_mark
        reason += f" ({e.context} started at line {cm.line + 1}, column {cm.column + 1})"
    line, col = (mark.line + 1, mark.column + 1) if mark is not None else (None, None)
    return SpecError.single(source, reason, line=line, column=col)


def _duplicate_key_error(e: DuplicateKeyError, text: str, source: str) -> SpecError:
    mark = e.problem_mark
    line, col = mark.line + 1, mark.column + 1
    # The constructor does not say where the mapping sits; composing (no duplicate check) does.
    found = _find_key_node(YAML(typ="rt").compose(text), (mark.line, mark.column))
    if found is None:
        m = re.search(r'duplicate key "(.*)" with value', e.problem or "")
        name = m.group(1) if m else "?"
        return SpecError.single(source, f"duplicate key '{name}'", key=name, line=line, column=col)
    path, first_line = found
    name = str(path[-1])
    return SpecError.single(
        source,
        f"duplicate key '{name}' (first given on line {first_line})",
        key=format_key(path),
        line=line,
        column=col,
    )


def _find_key_node(node: Any, at: tuple[int, int]) -> tuple[KeyPath, int] | None:
    """Key path of the mapping key starting at `at`, and the line of its first occurrence."""
    stack: list[tuple[Any, KeyPath]] = [(node, ())]
    seen: set[int] = set()
    while stack:
        node, path = stack.pop()
        if id(node) in seen:
            continue
        seen.add(id(node))
        if isinstance(node, MappingNode):
            first: dict[str, int] = {}
            for knode, vnode in node.value:
                name = knode.value if isinstance(knode, ScalarNode) else str(knode.value)
                first.setdefault(name, knode.start_mark.line + 1)
                if (knode.start_mark.line, knode.start_mark.column) == at:
                    return path + (name,), first[name]
                stack.append((vnode, path + (name,)))
        elif isinstance(node, SequenceNode):
            stack.extend((child, path + (i,)) for i, child in enumerate(node.value))
    return None


def _plain(node: Any, path: KeyPath, doc: Document, done: set[int], repeated: bool) -> Any:
    """Round-trip tree -> dict/list/str/int/float/bool/None, recording positions.

    `done`: collections converted before (met again, they are an alias, whose values count against
    MAX_ALIAS_VALUES). Recursive aliases were refused before (`_refuse_recursion`).
    """
    if repeated:
        doc.alias_values += 1
        if doc.alias_values > MAX_ALIAS_VALUES:
            raise SpecError.single(doc.source, f"YAML aliases repeat more than {MAX_ALIAS_VALUES} values "
                                   f"(a spec needs a few dozen)", key=format_key(path))
    if isinstance(node, (dict, list)):
        if len(path) >= MAX_DEPTH:
            raise SpecError.single(doc.source, f"nested deeper than {MAX_DEPTH} levels (a spec nests 4)",
                                   key=format_key(path[:MAX_DEPTH]))
        repeated = repeated or id(node) in done
        done.add(id(node))
    if isinstance(node, dict):
        doc.at_key.add(path)
        lc = getattr(getattr(node, "lc", None), "data", None) or {}
        out: dict[str, Any] = {}
        for k, v in node.items():
            name = k if isinstance(k, str) else str(_scalar(k))
            sub = path + (name,)
            pos = lc.get(k)  # merged (`<<`) keys have no position of their own
            if pos is not None:
                doc.key_pos[sub] = (pos[0] + 1, pos[1] + 1)
                doc.value_pos[sub] = (pos[2] + 1, pos[3] + 1)
            if name in out:
                line, col = doc.key_pos.get(sub, (None, None))
                raise SpecError.single(
                    doc.source, f"duplicate key '{name}'", key=format_key(sub), line=line, column=col
                )
            out[name] = _plain(v, sub, doc, done, repeated)
        return out
    if isinstance(node, list):
        doc.at_key.add(path)
        lc = getattr(getattr(node, "lc", None), "data", None) or {}
        items = []
        for i, v in enumerate(node):
            sub = path + (i,)
            pos = lc.get(i)
            if pos is not None:
                doc.value_pos[sub] = (pos[0] + 1, pos[1] + 1)
            items.append(_plain(v, sub, doc, done, repeated))
        return items
    if node is None:
        doc.at_key.add(path)
    return _scalar(node)


def _scalar(v: Any) -> Any:
    # bool before int: ruamel's ScalarBoolean (like bool) is an int subclass
    if v is None or type(v) in (str, int, float, bool):
        return v
    if isinstance(v, bool) or type(v).__name__ == "ScalarBoolean":
        return bool(v)
    if isinstance(v, int):
        return int(v)
    if isinstance(v, float):
        return float(v)
    if isinstance(v, str):
        return str(v)
    if type(v).__name__ == "TaggedScalar" and str(v.tag) == _YAML_TAG + "str":  # `!!str 1` is the text "1"
        return str(v.value)
    return v  # timestamps, tagged scalars: left for validation to reject (base.show writes them as in YAML)


def format_key(path: KeyPath) -> str:
    """('grid', 'force_ratio', 2) -> 'grid.force_ratio[2]'."""
    out = ""
    for part in path:
        if isinstance(part, int):
            out += f"[{part}]"
        else:
            out += f".{part}" if out else str(part)
    return out
