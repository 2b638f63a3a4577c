"""No traceback on any input: generated bad configurations, TOML files,
``--set`` values and ``--out`` paths each exit with code 2 and a one-line message, and
create nothing.

The values are bad by construction: read from the schema (each number outside its range,
a non-integer for an integer, a word for a choice, a non-boolean for a switch), unknown
keys, broken TOML, and output paths that cannot be a run directory. A value that slipped
through would start a simulation: ``run_simulation`` is replaced by a failure.
"""

from __future__ import annotations

import contextlib
import io
import math
import os
import tempfile
from pathlib import Path
from types import NoneType
from typing import Annotated, Any, Literal, Union, get_args, get_origin

import annotated_types as at
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import granflow.runner as runner
from granflow.cli import main
from granflow.config import MAX_TRIANGLES, SECTIONS, load_config
from granflow.config.schema import FLOORS

SCENARIOS = ["plug-flow", "trapezoid-rigid", "rectangle-rigid", "trapezoid-erodible"]
WORD = st.text(alphabet="abcdefghijklmnopqrstuvwxyz_-", min_size=1, max_size=12)


def _bounds(annotation: Any, metadata: list[Any]) -> tuple[Any, dict[str, float]]:
    """(base type, {gt/ge/lt/le: bound}) of a field's annotation (None dropped)."""
    bounds: dict[str, float] = {}
    tp = annotation
    while True:
        origin = get_origin(tp)
        if origin in (Union, type(int | None)):   # a number, or none, or words
            args = [a for a in get_args(tp) if a is not NoneType]
            numbers = [a for a in args if get_origin(a) is not Literal]
            if len(args) != 1 and len(numbers) != 1:
                return tp, bounds
            args = args if len(args) == 1 else numbers
            tp = args[0]
        elif origin is Annotated:
            metadata = [*metadata, *tp.__metadata__]
            tp = get_args(tp)[0]
        else:
            break
    for item in metadata:
        for m in getattr(item, "metadata", [item]):
            for cls, key in ((at.Gt, "gt"), (at.Ge, "ge"), (at.Lt, "lt"), (at.Le, "le")):
                if isinstance(m, cls):
                    bounds[key] = float(getattr(m, key))
    return tp, bounds


def bad_values(section: str, key: str) -> st.SearchStrategy[str]:
    """TOML literals that the field ``section.key`` must refuse."""
    field = SECTIONS[section].model_fields[key]
    tp, bounds = _bounds(field.annotation, list(field.metadata))
    words = WORD.filter(lambda w: w != "none").map(lambda w: f'"{w}"')
    if get_origin(tp) is Literal or get_origin(field.annotation) in (Union, type(int | None)) and \
            any(get_origin(a) is Literal for a in get_args(field.annotation)):
        choices = {a for t in [tp, *get_args(field.annotation)] if get_origin(t) is Literal
                   for a in get_args(t)}
        return st.one_of(words.filter(lambda w: w.strip('"') not in choices),
                         st.sampled_from(["[1, 2]", "true"]))
    if tp is bool:
        return st.sampled_from(["1", "0", '"yes"', '"true"', "[true]", "2.5"])
    if get_origin(tp) is list:
        return st.one_of(st.floats(allow_nan=False).map(repr), words,
                         st.just('["a", 0.1]'), st.just("[nan]"))
    low = bounds.get("gt", bounds.get("ge", -math.inf))
    high = bounds.get("lt", bounds.get("le", math.inf))
    outside = []
    if math.isfinite(low):
        below = (st.floats(max_value=low, exclude_max="ge" in bounds, allow_nan=False,
                           allow_infinity=True)
                 if "gt" in bounds or "ge" in bounds else st.nothing())
        outside.append(below.filter(lambda v: v < low or ("gt" in bounds and v == low)))
    if math.isfinite(high):
        outside.append(st.floats(min_value=high, allow_nan=False, allow_infinity=True)
                       .filter(lambda v: v > high or ("lt" in bounds and v == high)))
    specials = st.sampled_from(["nan", "inf", "-inf", '"abc"', "[1.0]", "true"])
    if tp is int:
        outside.append(st.floats(allow_nan=False, allow_infinity=False)
                       .filter(lambda v: not v.is_integer() and low < v < high))
    values = st.one_of(*outside).map(repr) if outside else st.nothing()
    return st.one_of(values, specials)


FIELDS = [(s, k) for s, model in SECTIONS.items() for k in model.model_fields]


@st.composite
def bad_set(draw: st.DrawFn) -> list[str]:
    """``run SCENARIO --set section.key=BAD``, or an unknown key or a malformed --set."""
    scenario = draw(st.sampled_from(SCENARIOS))
    kind = draw(st.sampled_from(["value", "value", "value", "unknown", "malformed", "tiny"]))
    if kind == "tiny":         # a mesh Netgen would take hours to make
        size = draw(st.floats(min_value=1e-12, max_value=1e-4))
        assignment = f"mesh.size={size!r}"
    elif kind == "value":
        section, key = draw(st.sampled_from(FIELDS))
        assignment = f"{section}.{key}={draw(bad_values(section, key))}"
    elif kind == "unknown":
        section = draw(st.sampled_from([*SECTIONS, "solver", "mesh2"]))
        known = SECTIONS[section].model_fields if section in SECTIONS else {}
        key = draw(WORD.filter(lambda w: w not in known))
        assignment = f"{section}.{key}=1"
    else:
        assignment = draw(st.sampled_from(["", "=", "numerics.eps", "=1", ".=2", "eps=1"]))
    return ["run", scenario, "--set", assignment]


@st.composite
def bad_toml(draw: st.DrawFn) -> tuple[str, list[str]]:
    """A scenario file that is broken TOML, names an unknown section/key/scenario, or sets a
    bad value; returns (file text, arguments)."""
    kind = draw(st.sampled_from(["garbage", "section", "key", "scenario", "value", "type"]))
    if kind == "garbage":
        text = draw(st.sampled_from(["[", "a = ", "x = [1,", "[numerics\neps = 1", "= 3",
                                     'scenario = "plug-flow"\nscenario = "x"']))
    elif kind == "section":
        text = f"[{draw(WORD.filter(lambda w: w not in SECTIONS))}]\nx = 1\n"
    elif kind == "key":
        section = draw(st.sampled_from(list(SECTIONS)))
        key = draw(WORD.filter(lambda w: w not in SECTIONS[section].model_fields))
        text = f"[{section}]\n{key} = 1\n"
    elif kind == "scenario":
        text = f'scenario = "{draw(WORD.filter(lambda w: w not in SCENARIOS))}"\n'
    elif kind == "type":
        section = draw(st.sampled_from(list(SECTIONS)))
        text = f"{section} = {draw(st.sampled_from(['1', '[1, 2]', 'true']))}\n"
    else:
        section, key = draw(st.sampled_from(FIELDS))
        base = draw(st.sampled_from(SCENARIOS))
        text = f'scenario = "{base}"\n[{section}]\n{key} = {draw(bad_values(section, key))}\n'
    return text, ["run", "case.toml"]


OUT_PATHS = ["", "a_file", "a_file/run", "foreign", "foreign/", "/proc/granflow-run",
             "/dev/null/run"]


@st.composite
def bad_out(draw: st.DrawFn) -> list[str]:
    """``run --out PATH`` where PATH cannot be a fresh run directory."""
    return ["run", draw(st.sampled_from(SCENARIOS)), "--out", draw(st.sampled_from(OUT_PATHS)),
            "--quiet"]


def _tree(root: Path) -> list[str]:
    return sorted(str(p.relative_to(root)) for p in root.rglob("*"))


def _refuse_to_run(*args: Any, **kwargs: Any) -> dict[str, Any]:
    raise AssertionError("a bad input was accepted and a simulation started")


@pytest.fixture(autouse=True)
def no_simulation(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(runner, "run_simulation", _refuse_to_run)


def check_refused(args: list[str], toml: str | None = None) -> None:
    with tempfile.TemporaryDirectory() as tmp:
        root = Path(tmp)
        (root / "a_file").write_text("not a folder\n")
        (root / "foreign").mkdir()
        (root / "foreign" / "notes.txt").write_text("mine\n")
        if toml is not None:
            (root / "case.toml").write_text(toml)
        before = _tree(root)
        err, cwd = io.StringIO(), os.getcwd()
        os.chdir(root)
        try:
            with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
                try:
                    code = main(args)
                except SystemExit as exit_:
                    code = exit_.code
        finally:
            os.chdir(cwd)
        message = err.getvalue()
        assert code == 2, (args, toml, message)
        assert message.startswith("granflow: error: ") and message.count("\n") == 1, message
        assert "Traceback" not in message
        assert _tree(root) == before, (args, toml)


SETTINGS = settings(max_examples=150, deadline=None, derandomize=True,
                    suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])


@SETTINGS
@given(bad_set())
def test_bad_set_values_exit_2_with_one_line(args: list[str]) -> None:
    check_refused(args)


@SETTINGS
@given(bad_toml())
def test_bad_scenario_files_exit_2_with_one_line(case: tuple[str, list[str]]) -> None:
    text, args = case
    check_refused(args, text)


@settings(max_examples=30, deadline=None, derandomize=True)
@given(bad_out())
def test_bad_out_paths_exit_2_with_one_line(args: list[str]) -> None:
    check_refused(args)


def test_the_schema_bounds_are_what_the_generator_reads() -> None:
    """The generator derives bad values from the schema: check it reads a known bound."""
    _, bounds = _bounds(SECTIONS["mesh"].model_fields["size"].annotation,
                        list(SECTIONS["mesh"].model_fields["size"].metadata))
    assert bounds == {"gt": 0.0, "le": 1e3}
    assert load_config("trapezoid-rigid").mesh.size > 0 and MAX_TRIANGLES > 0


DEEP = "a = " + "[" * 5000 + "]" * 5000 + "\n"


@pytest.mark.parametrize("args, toml", [
    (["run", "case.toml"], "scenario = [1]\n"),
    (["run", "case.toml"], "scenario = {a = 1}\n"),
    (["run", "case.toml"], DEEP),
    (["run", "case.toml"], "[mesh]\nsize = " + "[" * 3000 + "]" * 3000 + "\n"),
    (["sweep", "case.toml"], DEEP),
    (["run", "/dev/zero"], None),
    (["run", "/dev/urandom"], None),
    (["sweep", "/dev/zero"], None),
    (["run", "rectangle-rigid", "--set", "mesh.size=1e-320"], None),
    (["run", "plug-flow", "--set", "mesh.size=1e-320"], None),
    (["run", "trapezoid-erodible", "--set", "geometry.erodible_thickness=1e-320"], None),
    (["run", "plug-flow", "--set", "material.viscosity=5e-324"], None),
    (["run", "plug-flow", "--set", "time.dt=1e-12"], None),
    (["run", "trapezoid-rigid", "--set", "time.dt_max=1e-12"], None),
    (["run", "plug-flow", "--set", "numerics.tol=5e-324"], None),
    (["run", "trapezoid-rigid", "--set", "mesh.size=0.001"], None),
    (["verify", "plug-flow", "--out", "a_file"], None),
    (["verify", "plug-flow", "--scheduler", "foo"], None),
    (["run", "trapezoid-rigid", "--set", "geometry.front_angle_deg=5e-324"], None),
    (["run", "trapezoid-rigid", "--set", "geometry.width=" + "1" * 5000], None),
    (["run", "case.toml"], "[geometry]\nwidth = " + "1" * 5000 + "\n"),
    (["run", "trapezoid-rigid", "--set", "numerics.tol=1e-14"], None),
    (["run", "trapezoid-rigid", "--set", "time.t_end=10000", "--set",
      "time.stop_at_rest=false"], None),
    (["run", "trapezoid-rigid", "--set", "geometry.width=1000"], None),
    (["run", "trapezoid-rigid", "--set", "mesh.size=0.0012"], None),
    (["run", "rectangle-rigid", "--set", "time.t_end=0.01", "--set",
      "time.output_times=[" + ", ".join(f"{0.0005 * k:g}" for k in range(1, 20)) + "]"], None),
    (["run", "trapezoid-rigid", "--out", ""], None),
    (["verify", "plug-flow", "--out", ""], None),
    (["sweep", "case.toml"], 'base = "rectangle-rigid"\n[vary]\n"mesh.size" = ['
     + ", ".join(["0.05"] * 101) + ']\n"geometry.height" = [' + ", ".join(["0.1"] * 101)
     + "]\n"),
    (["run", "cylinder-rigid", "--set", "gate.enabled=true"], None),
], ids=["scenario-list", "scenario-table", "deep-arrays", "deep-value", "deep-sweep",
        "dev-zero", "dev-urandom", "sweep-dev-zero", "tiny-mesh", "tiny-plug-mesh",
        "tiny-layer", "tiny-viscosity", "tiny-dt", "tiny-dt-max", "tiny-tol", "huge-mesh",
        "verify-out-file", "verify-scheduler", "front-angle-5e-324", "5000-digits",
        "5000-digits-file", "tol-1e-14", "t-end-10000-no-rest", "width-1000", "mesh-0.0012",
        "more-outputs-than-steps", "run-out-empty", "verify-out-empty", "sweep-10201-runs",
         "gate-on-a-cylinder"])
def test_the_last_bad_inputs_exit_2_with_one_line(args: list[str], toml: str | None) -> None:
    """Each once ended in a traceback, a hang or hours of computing."""
    check_refused(args, toml)


def _field_bounds(section: str, key: str) -> tuple[Any, dict[str, float]]:
    field = SECTIONS[section].model_fields[key]
    return _bounds(field.annotation, list(field.metadata))


POSITIVE = [(s, k) for s, k in FIELDS if _field_bounds(s, k)[0] is float and (
    "gt" in _field_bounds(s, k)[1] or _field_bounds(s, k)[1].get("ge", 0.0) > 0)]
WHERE_EFFECTIVE = {"layer": ["trapezoid-erodible"], "gate": ["trapezoid-rigid", "--set",
                                                             "gate.enabled=true"],
                   "surface_tension": ["trapezoid-rigid", "--set",
                                       "surface_tension.enabled=true"]}


@pytest.mark.parametrize("value", ["5e-324", "1e-310"])
@pytest.mark.parametrize("section, key", POSITIVE, ids=[f"{s}.{k}" for s, k in POSITIVE])
def test_a_subnormal_value_is_refused_by_the_keys_own_bound(section: str, key: str,
                                                           value: str) -> None:
    """Keys whose natural bound is 0 have a physical smallest value (``FLOORS``, shown in
    docs/parameters.md): 11 of them took 5e-324 and failed mid-run."""
    where = WHERE_EFFECTIVE.get(section, ["plug-flow" if key == "length" else
                                          "trapezoid-rigid"])
    check_refused(["run", *where, "--set", f"{section}.{key}={value}"])


# a law's keys refused where the law is on (elsewhere they are refused as keys without
# effect): 5e-324 passed each of them once, as it did gate.tau and numerics.al_r
WITH_THE_LAW = {
    "i0": ["--set", "material.rheology=mu-i"],
    "nonlocal_b": ["--set", "material.rheology=nonlocal", "--set",
                   "material.friction_angle_deg=20.9"],
    "mobilisation_time": ["--set", "material.friction=hysteretic"],
    "rest_time": ["--set", "material.friction=hysteretic"],
}


@pytest.mark.parametrize("section", ["material", "layer"])
@pytest.mark.parametrize("key", sorted(WITH_THE_LAW))
def test_a_subnormal_law_key_is_refused_where_the_law_is_on(section: str, key: str) -> None:
    law = WITH_THE_LAW[key]
    check_refused(["run", "trapezoid-erodible", *law, "--set", f"{section}.{key}=5e-324"])


@pytest.mark.parametrize("args", [
    ["run", "trapezoid-rigid", "--set", "gate.enabled=true", "--set",
     "gate.speed_law=exponential", "--set", "gate.tau=5e-324"],
    ["run", "rectangle-rigid", "--set", "numerics.method=augmented-lagrangian", "--set",
     "numerics.al_r=5e-324"],
    *[["run", scenario, "--set", "geometry.erodible_thickness=5e-324"]
      for scenario in ("trapezoid-erodible", "trapezoid-rigid", "cylinder-erodible")],
], ids=["gate-tau", "al-r", "layer-erodible", "layer-rigid", "layer-cylinder"])
def test_the_probes_last_subnormal_values_are_one_line(args: list[str]) -> None:
    """A layer 5e-324 m thick divided by zero while its triangles were counted."""
    check_refused(args)


def test_a_subnormal_layer_is_refused_from_python_too() -> None:
    import granflow
    from granflow.config import ConfigError

    with pytest.raises(ConfigError, match=r"geometry.erodible_thickness = 5e-324 .* inf "
                                          "triangles in the layer"):
        granflow.run("trapezoid-erodible", {"geometry.erodible_thickness": 5e-324})


def test_each_floor_is_the_bound_of_its_key() -> None:
    for name, floor in FLOORS.items():
        assert _field_bounds(*name.split("."))[1]["ge"] == floor.value, name
        assert floor.why in (Path(__file__).parents[1] / "docs" / "parameters.md").read_text()


LONG = "n" * 300


@pytest.mark.parametrize("command", [["sweep", "aspect-ratio"], ["converge", "rectangle-rigid"]])
@pytest.mark.parametrize("option", [
    ["--out", "a_file"], ["--out", "a_file/run"], ["--out", "/proc/granflow-x"],
    ["--out", "/dev/null"], ["--out", "/dev/null/x"], ["--out", LONG], ["--out", ""],
    ["--out", "."], ["--scheduler", "ucx://10.0.0.1:8786"],
    ["--scheduler", "tls://10.0.0.1:8786"], ["--scheduler", "tcp://10.0.0.1:99999"],
    ["--scheduler", "tcp://10.0.0.1"]],
    ids=["file", "under-file", "proc", "dev-null", "under-dev-null", "long-name", "empty",
         "current", "ucx", "tls", "port-99999", "no-port"])
def test_sweep_and_converge_outputs_and_schedulers_exit_2(command: list[str],
                                                         option: list[str]) -> None:
    """Refused before a cluster starts or a folder is made."""
    check_refused([*command, *option])


def test_a_run_of_hours_is_announced_before_it_starts(monkeypatch: pytest.MonkeyPatch) -> None:
    """Valid but long (a 1 us fixed step to rest): a note with the estimate, then the run."""
    err = io.StringIO()
    with tempfile.TemporaryDirectory() as tmp, contextlib.redirect_stderr(err), \
            contextlib.redirect_stdout(io.StringIO()), pytest.raises(AssertionError,
                                                                     match="started"):
        main(["run", "trapezoid-rigid", "--set", "time.dt=1e-6", "--out", f"{tmp}/run"])
    note = err.getvalue().strip()
    assert note.startswith("granflow: note: this run needs about ") and "hours" in note
    assert "time.dt" in note and note.count("\n") == 0
