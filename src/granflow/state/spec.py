"""What a part's share of the checkpoint may hold: declared beside the part, checked in one
place before any part reads it.

A resumed run reads its state from a file that may come from someone else
(``io/checkpoint.py`` decodes it as data only). Each part that gives a share of the state
(``save_state``) declares it as a ``Share``: its members by name and what each may be (a
time, a count, a list of numbers, an array of floats with two columns, one of the listed
dataclasses...). ``check_share`` checks a share against its declaration and returns it with
the declared members only, so that nothing undeclared reaches a part; a member of the wrong
type, range or shape is a ``StateError`` of one line that names it:
``scenario.mover.initial_area = 'x' is not a number > 0``.

Array sizes and list lengths named by a dimension ("cells", "markers") must agree wherever
the name appears in one state; a mesh member sets "cells" and "vertices" (``mesh``).
"""

from __future__ import annotations

import dataclasses
import math
import re
import types
import typing
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any, Union

import numpy as np

Dims = dict[str, int]
MAX_TEXT = 200


class StateError(ValueError):
    """A member of a checkpoint's state is not what its part declared (one line)."""


@dataclass(frozen=True)
class Check:
    """What a member may be: ``what`` says it in words, ``test`` is True when it is
    (given the state's dimensions, which it may set); ``optional``: an older checkpoint may
    lack the member."""

    what: str
    test: Callable[[Any, str, Dims], bool]
    optional: bool = False
    inner: Callable[[Any, str, Dims], Any] | None = None   # a container's members

    def __call__(self, value: Any, where: str, dims: Dims) -> Any:
        if not self.test(value, where, dims):
            raise StateError(f"{where} = {_shown(value)} is not {self.what}")
        return self.inner(value, where, dims) if self.inner is not None else value


Share = Mapping[str, Check]


def _real(x: Any) -> bool:
    return isinstance(x, int | float) and not isinstance(x, bool)


def number(low: float = -math.inf, *, above: bool = False) -> Check:
    """A finite number >= ``low`` (> with ``above``)."""
    bound = "" if low == -math.inf else f" {'>' if above else '>='} {low:g}"
    return Check(f"a number{bound}", lambda x, w, d: _real(x) and math.isfinite(x) and (
        x > low if above else x >= low))


def whole(low: int = 0) -> Check:
    return Check(f"a whole number >= {low}",
                 lambda x, w, d: isinstance(x, int) and not isinstance(x, bool) and x >= low)


TIME = number(0.0)
POSITIVE = number(0.0, above=True)
REAL = number()
ANY_NUMBER = Check("a number (NaN or infinite too)", lambda x, w, d: _real(x))  # a measure
COUNT = whole()
FLAG = Check("true or false", lambda x, w, d: isinstance(x, bool))
TEXT = Check(f"a text of at most {MAX_TEXT} characters",
             lambda x, w, d: isinstance(x, str) and len(x) <= MAX_TEXT)


def text(pattern: str, what: str) -> Check:
    return Check(what, lambda x, w, d: isinstance(x, str) and re.fullmatch(pattern, x) is not None)


def may_lack(check: Check) -> Check:
    """``check``, for a member that checkpoints of an earlier granflow do not have."""
    return dataclasses.replace(check, optional=True)


def or_none(check: Check) -> Check:
    return Check(f"{check.what} or null", lambda x, w, d: x is None or check.test(x, w, d),
                 inner=lambda x, w, d: None if x is None else check(x, w, d))


def list_of(check: Check, length: str | None = None, most: int | None = None) -> Check:
    """A list (or tuple) of members, each ``check``; ``length`` names its length's
    dimension, ``most`` bounds it."""
    def members(x: Any, where: str, dims: Dims) -> list[Any]:
        _size(dims, length, len(x), where)
        return [check(v, f"{where}[{i}]", dims) for i, v in enumerate(x)]
    bound = "" if most is None else f" (at most {most})"
    return Check(f"a list of {check.what}s{bound}", lambda x, w, d: isinstance(
        x, list | tuple) and (most is None or len(x) <= most), inner=members)


def tuple_of(*checks: Check) -> Check:
    """A list or tuple of exactly these members (stored as a tuple)."""
    def members(x: Any, where: str, dims: Dims) -> tuple[Any, ...]:
        return tuple(check(v, f"{where}[{i}]", dims)
                     for i, (check, v) in enumerate(zip(checks, x, strict=True)))
    return Check(f"a list of {len(checks)} members",
                 lambda x, w, d: isinstance(x, list | tuple) and len(x) == len(checks),
                 inner=members)


def mapping(check: Check) -> Check:
    """A dict of text keys to members, each ``check``."""
    return Check(f"a table of {check.what}s",
                 lambda x, w, d: isinstance(x, dict) and all(TEXT.test(k, w, d) for k in x),
                 inner=lambda x, w, d: {k: check(v, f"{w}.{k}", d) for k, v in x.items()})


def record(share: Share) -> Check:
    """A dict with the members of ``share`` (the others are dropped)."""
    return Check("a table", lambda x, w, d: isinstance(x, dict),
                 inner=lambda x, w, d: check_share(x, share, w, d))


def array(*shape: int | str | None, kind: str = "f", rows: int = 0) -> Check:
    """A NumPy array of finite values of this dtype kind ("f": floats, "i": integers) and
    shape: a number, a dimension's name, or None for any size; at least ``rows`` rows."""
    def test(x: Any, where: str, dims: Dims) -> bool:
        if not isinstance(x, np.ndarray) or x.dtype.kind not in kind or \
                x.ndim != len(shape) or len(x) < rows:
            return False
        if any(isinstance(n, int) and n != m for n, m in zip(shape, x.shape, strict=True)):
            return False
        for name, size in zip(shape, x.shape, strict=True):
            _size(dims, name if isinstance(name, str) else None, size, where)
        return x.dtype.kind != "f" or bool(np.isfinite(x).all())
    sizes = ", ".join("n" if n is None else str(n) for n in shape)
    least = f", n >= {rows}" if rows else ""
    return Check(f"an array of finite {'floats' if kind == 'f' else 'integers'} of shape "
                 f"({sizes}{least})", test)


def instance(cls: type, what: str, sizes: Callable[[Any], Dims] | None = None) -> Check:
    """An object of class ``cls`` (built by the reader, e.g. a mesh); ``sizes`` gives the
    dimensions it sets."""
    def test(x: Any, where: str, dims: Dims) -> bool:
        if not isinstance(x, cls):
            return False
        for name, size in (sizes(x) if sizes is not None else {}).items():
            _size(dims, name, size, where)
        return True
    return Check(what, test)


def dataclass_of(*classes: type) -> Check:
    """An instance of one of these dataclasses, each field checked by its annotation (its
    ``Annotated`` check, else its type's: a float is then any number)."""
    names = " or ".join(c.__name__ for c in classes)

    def fields(x: Any, where: str, dims: Dims) -> Any:
        hints = typing.get_type_hints(type(x), include_extras=True)
        for f in dataclasses.fields(x):
            setattr(x, f.name, _annotated(hints[f.name])(getattr(x, f.name),
                                                          f"{where}.{f.name}", dims))
        return x
    return Check(f"a {names}", lambda x, w, d: type(x) in classes, inner=fields)


def check_share(share: Any, spec: Share, where: str, dims: Dims | None = None
                ) -> dict[str, Any]:
    """``share`` with the members ``spec`` declares, each checked (module docstring)."""
    dims = {} if dims is None else dims
    if not isinstance(share, dict):
        raise StateError(f"{where} = {_shown(share)} is not a table")
    out = {}
    for name, check in spec.items():
        if name not in share:
            if check.optional:
                continue
            raise StateError(f"{where}.{name} is missing")
        out[name] = check(share[name], f"{where}.{name}", dims)
    return out


def assign(target: np.ndarray, values: Any, where: str) -> None:
    """``target[:] = values`` for values of exactly its shape (NumPy would spread a single
    value over all)."""
    values = np.asarray(values)
    if values.shape != target.shape:
        raise StateError(f"{where} has shape {values.shape}, not {target.shape}")
    target[...] = values


def _annotated(tp: Any) -> Check:
    """The check of a dataclass field's annotation (``Annotated[float, check]`` says its
    own)."""
    origin, args = typing.get_origin(tp), typing.get_args(tp)
    if origin is typing.Annotated:
        return next((a for a in args[1:] if isinstance(a, Check)), None) or _annotated(args[0])
    if origin in (Union, types.UnionType) and type(None) in args:
        rest = [a for a in args if a is not type(None)]
        return or_none(_annotated(rest[0]))
    if origin is list:
        return list_of(_annotated(args[0]))
    if origin is tuple:
        return tuple_of(*map(_annotated, args))
    if origin is dict:
        return mapping(_annotated(args[1]))
    simple = {bool: FLAG, int: COUNT, float: ANY_NUMBER, str: TEXT, np.ndarray: array(None)}
    if tp not in simple:
        raise TypeError(f"no state check for a field of type {tp}")
    return simple[tp]


def _size(dims: Dims, name: str | None, size: int, where: str) -> None:
    if name is None:
        return
    if dims.setdefault(name, size) != size:
        raise StateError(f"{where} has {size} {name} where the state has {dims[name]}")


def _shown(value: Any) -> str:
    if isinstance(value, np.ndarray):
        return f"an array {value.dtype} of shape {value.shape}"
    text = repr(value)
    return text if len(text) <= 40 else f"{text[:37]}..."
