"""One-line messages for invalid configuration values, read from the schema's types and
bounds: ``section.key = value: must be a number in (0, 1000]``; and the notes (warnings)
about valid ones, which point at the user's own line."""

from __future__ import annotations

import contextlib
import sys
import warnings
from collections.abc import Iterator, Mapping, Sequence
from pathlib import Path
from types import NoneType, UnionType
from typing import Annotated, Any, Literal, Union, get_args, get_origin

import annotated_types as at
from pydantic import BaseModel
from pydantic.fields import FieldInfo

from granflow.config.schema import ConfigNote, RegisteredKind

_PACKAGE = str(Path(__file__).resolve().parents[1])   # granflow's own source files


def note(message: str) -> None:
    """Warn with a ``ConfigNote`` attributed to the first caller outside granflow (the
    user's line in a script or notebook), never to a line of granflow's source."""
    frame, level = sys._getframe(1), 2
    while frame is not None and str(Path(frame.f_code.co_filename).resolve()).startswith(
            _PACKAGE):
        frame, level = frame.f_back, level + 1
    warnings.warn(message, ConfigNote, stacklevel=level)


def show_note(message: Warning | str, category: type[Warning], filename: str, lineno: int,
              file: object = None, line: str | None = None) -> None:
    """``warnings.showwarning`` that prints a configuration note (``ConfigNote``) as one
    line, ``granflow: note: ...``, and other warnings as Python shows them."""
    if issubclass(category, ConfigNote):
        print(f"granflow: note: {message}", file=sys.stderr)
    else:
        sys.stderr.write(warnings.formatwarning(message, category, filename, lineno, line))


@contextlib.contextmanager
def notes_as_lines() -> Iterator[None]:
    """Within: each configuration note once, as one line (the command line, and each run
    of a sweep in its Dask worker, where Python would show the worker's source line)."""
    with warnings.catch_warnings():
        warnings.simplefilter("default", ConfigNote)
        warnings.showwarning = show_note
        yield


def one_line(error: Any, data: dict[str, Any], sections: Mapping[str, type[BaseModel]]) -> str:
    """``section.key = value: must be ...`` from the first pydantic error."""
    loc = error["loc"]
    if error["type"] == "granflow_config":
        return error["ctx"]["message"]
    if len(loc) < 2 or loc[0] not in sections:
        return f"{'.'.join(map(str, loc)) or 'configuration'}: {error['msg']}"
    section, key = loc[0], loc[1]
    model = sections[section]
    if key not in model.model_fields:
        return f"unknown configuration key '{section}.{key}'"
    field = model.model_fields[key]
    allowed = describe(field.annotation, field.metadata)
    if error["type"] == "missing":
        return f"{section}.{key} is not set: it must be {allowed}"
    value = data.get(section, {}).get(key, error.get("input"))
    return f"{section}.{key} = {fmt_value(value)}: must be {allowed}"


def describe(tp: Any, metadata: Sequence[Any] = ()) -> str:
    """Plain words for the values a field accepts, read from its type and bounds."""
    origin, args = get_origin(tp), get_args(tp)
    if origin in (Union, UnionType):
        text = " or ".join(describe(a) for a in args if a is not NoneType)
        return text + (" or none" if NoneType in args else "")
    if origin is Annotated:
        return describe(args[0], [*metadata, *tp.__metadata__])
    kind = next((m for m in metadata if isinstance(m, RegisteredKind)), None)
    if kind is not None:
        return kind.allowed()
    if origin is Literal:
        names = [repr(a) for a in args]
        return names[0] if len(names) == 1 else "one of " + ", ".join(names)
    if tp is bool:
        return "true or false"
    if origin is list:
        inner = get_args(args[0])[0] if args and get_origin(args[0]) is Annotated else None
        most = next((m.max_length for item in metadata for m in (
            item.metadata if isinstance(item, FieldInfo) else [item])
            if isinstance(m, at.MaxLen)), None)
        size = "" if most is None else f" at most {most:,}".replace(",", " ")
        return (f"a list of{size} [x, z] points" if get_origin(inner) is list
                else f"a list of{size} numbers")
    if tp is str:
        return "a string"
    bounds: dict[str, float] = {}
    for item in metadata:
        for m in item.metadata if isinstance(item, FieldInfo) else [item]:
            for cls, sym in ((at.Gt, "gt"), (at.Ge, "ge"), (at.Lt, "lt"), (at.Le, "le")):
                if isinstance(m, cls):
                    bounds[sym] = getattr(m, sym)
    noun = "an integer" if tp is int else "a number"
    lo = ("(", bounds["gt"]) if "gt" in bounds else ("[", bounds["ge"]) if "ge" in bounds else None
    hi = (")", bounds["lt"]) if "lt" in bounds else ("]", bounds["le"]) if "le" in bounds else None
    if lo and hi:
        return f"{noun} in {lo[0]}{lo[1]:g}, {hi[1]:g}{hi[0]}"
    if lo:
        return f"{noun} {'>' if lo[0] == '(' else '>='} {lo[1]:g}"
    if hi:
        return f"{noun} {'<' if hi[0] == ')' else '<='} {hi[1]:g}"
    return noun


SHOWN = 6           # values of a long list shown in a message
SHOWN_CHARS = 80    # characters of a long value shown in a message


def fmt_value(value: Any) -> str:
    """A value as the user would write it (TOML-like: true, 'text', [1.0, 2.0], none);
    a long one shortened, so that a message stays one short line."""
    if value is None:
        return "none"
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, list | tuple):
        shown = ", ".join(fmt_value(v) for v in value[:SHOWN])
        more = f", ... ({len(value)} values)" if len(value) > SHOWN else ""
        return "[" + shown + more + "]"
    text = repr(value)
    return text if len(text) <= SHOWN_CHARS else f"{text[:SHOWN_CHARS - 3]}..."
