"""What a problem kind (``geometry.kind``) declares to the configuration: its cross-field
rules, the keys that have no effect on it, its cost estimate, how it refines in space, and
whether it has an erodible layer.

The configuration is the ground floor and knows no kind: each kind registers its
``KindRules`` from its own modules, beside its builder (``scenarios/``); the package imports
the built-in kinds when it is imported (``granflow/__init__.py``), so that every path to a
``Config`` finds them. A kind that is not registered is refused by name.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

Config = Any    # a validated configuration (schema.py: ConfigModel, which asks this registry)
Raw = dict[str, Any]     # a configuration's tables before validation


def _no_problems(c: Config) -> Iterator[str]:
    return iter(())


def _none(c: Config) -> dict[str, str]:
    return {}


def _never(c: Config) -> bool:
    return False


def _unchanged(data: Raw, base: Raw) -> None:
    return None


def _no_size(c: Config) -> float | None:
    return None


@dataclass(frozen=True)
class KindRules:
    """A problem kind as the configuration sees it.

    ``problems``: its cross-field checks, one line each naming the key; ``inert_keys``: the
    keys without effect on it, with the reason; ``triangles``: the triangles its mesher will
    make (bulk, erodible layer) and ``smallest_size``: the mesh.size that keeps them under a
    number; ``refine_space``: the keys a convergence study's level ``2^k`` sets for a finer
    mesh; ``erodible_layer``: whether a run has an erodible layer (and so [layer]'s
    material); ``stops_at_rest``: whether a run may end at rest before time.t_end;
    ``prepare``: before validation, on the raw tables (``data``) and what they would be
    without the user's settings (``base``); ``derived_size``: the mesh.size that other keys
    set, if they do; ``describe``: a few words for ``repr``; ``file_keys``: the
    "section.key" names of files, read relative to the TOML file that names them.
    """

    name: str
    describe: Callable[[Config], str]
    triangles: Callable[[Config], tuple[float, float]]
    smallest_size: Callable[[Config, float], float]
    refine_space: Callable[[Config, int], dict[str, Any]]
    problems: Callable[[Config], Iterator[str]] = _no_problems
    inert_keys: Callable[[Config], dict[str, str]] = _none
    erodible_layer: Callable[[Config], bool] = _never
    stops_at_rest: Callable[[Config], bool] = _never
    prepare: Callable[[Raw, Raw], None] = _unchanged
    derived_size: Callable[[Config], float | None] = _no_size
    file_keys: tuple[str, ...] = ()


KIND_RULES: dict[str, KindRules] = {}


def register_rules(rules: KindRules) -> KindRules:
    """Make ``rules`` those of ``geometry.kind = rules.name``."""
    KIND_RULES[rules.name] = rules
    return rules


def kind_names() -> list[str]:
    """The registered kinds, sorted."""
    return sorted(KIND_RULES)


def rules_of(c: Config) -> KindRules:
    """The registered rules of ``c``'s kind (the schema lets only those through)."""
    return KIND_RULES[c.geometry.kind]


def erodible_layer(c: Config) -> bool:
    """Whether the run of ``c`` has an erodible layer: the one question every part asks."""
    return rules_of(c).erodible_layer(c)


def anchor_paths(data: Raw, folder: Path) -> None:
    """The file paths a TOML file names (every kind's ``file_keys``), read from that file's
    folder when relative (in place, on the raw tables of one file)."""
    for section, key, value in _file_values(data):
        path = Path(value).expanduser()
        data[section][key] = str(path if path.is_absolute() else folder / path)


def absolute_paths(data: Raw) -> None:
    """File paths made absolute (relative ones: from the working folder), so that the
    resolved configuration reads the same files from anywhere."""
    for section, key, value in _file_values(data):
        data[section][key] = str(Path(value).expanduser().resolve())


def _file_values(data: Raw) -> Iterator[tuple[str, str, str]]:
    for rules in KIND_RULES.values():
        for name in rules.file_keys:
            section, key = name.split(".")
            table = data.get(section)
            value = table.get(key) if isinstance(table, dict) else None
            if isinstance(value, str) and value.lower() != "none" and value:
                yield section, key, value
