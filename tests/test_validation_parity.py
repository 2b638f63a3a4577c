"""One validation path: a key is refused, or accepted, the same way and for the same reason
whether it comes from `granflow show/run --set`, a TOML file, `Config.load(name, {...})`,
`Config.set` or `granflow.run(name, {...})`; only the words that name an interface differ."""

from __future__ import annotations

import contextlib
import io
import warnings
from pathlib import Path
from typing import Any

import pytest

import granflow
from granflow.cli import main
from granflow.config import Config, ConfigError, ConfigNote, load_config, toml_literal
from granflow.io.run_dir import RunDirError

REFUSED = [   # scenario, key, value, what the reason says
    ("rectangle-rigid", "geometry.length", 2.0, "describes the periodic layer"),
    ("plug-flow", "geometry.width", 0.5, "describes a column"),
    ("trapezoid-rigid", "material.i0", 0.3, "parameter of mu(I)"),
    ("trapezoid-rigid", "boundary.side_wall_friction_deg", 20.0, "channel_width = none"),
    ("rectangle-rigid", "geometry.front_angle_deg", 45.0, "vertical front"),
    ("trapezoid-rigid", "layer.density", 1400.0, "erodible layer's material"),
    ("trapezoid-rigid", "numerics.eps", -1.0, "must be a number in [1e-12, 1000]"),
    ("trapezoid-rigid", "mesh.size", 1e-6, "triangles"),
    ("trapezoid-rigid", "time.dt_init", 1.0, "must not exceed time.dt_max"),
    ("trapezoid-rigid", "time.output_times", [0.5, 0.1], "must be increasing"),
    ("trapezoid-rigid", "numerics.linearization", "secant", "must be one of"),
    ("trapezoid-rigid", "output.figure_format", "jpg", "one of 'png', 'pdf', 'svg'"),
    ("trapezoid-rigid", "output.dpi", 10, "an integer in [50, 1200]"),
    ("trapezoid-rigid", "geometry.hieght", 0.2, "unknown configuration key"),
]
ACCEPTED = [
    ("rectangle-rigid", "geometry.height", 0.2),
    ("trapezoid-rigid", "time.t_end", 0.5),           # with a note: later outputs dropped
    ("plug-flow", "mesh.cells_x", 4),
    ("plug-flow", "time.dt", None),
    ("trapezoid-rigid", "output.figure_format", "svg"),
    ("plug-flow", "geometry.width", 0.297),           # inert, but its default: harmless
]


def via_cli(scenario: str, key: str, value: Any) -> str:
    err = io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
        code = main(["show", scenario, "--set", f"{key}={toml_literal(value)}"])
    return err.getvalue().strip() if code else ""


def via_toml(tmp_path: Path, scenario: str, key: str, value: Any) -> Config:
    section, name = key.split(".")
    path = tmp_path / "case.toml"
    path.write_text(f'scenario = "{scenario}"\n[{section}]\n{name} = {toml_literal(value)}\n')
    return load_config(path)


def refusals(tmp_path: Path, scenario: str, key: str, value: Any) -> list[str]:
    """The message each interface gives."""
    out = [via_cli(scenario, key, value).removeprefix("granflow: error: ")]
    for attempt in (lambda: via_toml(tmp_path, scenario, key, value),
                    lambda: Config.load(scenario, {key: value}),
                    lambda: Config.load(scenario).set(key, value),
                    lambda: granflow.run(scenario, {key: value}, out=tmp_path / "run")):
        with pytest.raises(ConfigError) as info:
            attempt()
        out.append(str(info.value))
    return out


@pytest.mark.parametrize("scenario, key, value, reason", REFUSED)
def test_a_key_is_refused_alike_everywhere(tmp_path: Path, scenario: str, key: str,
                                           value: Any, reason: str) -> None:
    messages = refusals(tmp_path, scenario, key, value)
    assert len(set(messages)) == 1, messages
    assert reason in messages[0] and "\n" not in messages[0]
    assert not (tmp_path / "run").exists()                # refused before anything is made


@pytest.mark.parametrize("scenario, key, value", ACCEPTED)
def test_a_key_is_accepted_alike_everywhere(tmp_path: Path, scenario: str, key: str,
                                            value: Any) -> None:
    assert via_cli(scenario, key, value) == ""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConfigNote)
        configs = [via_toml(tmp_path, scenario, key, value),
                   Config.load(scenario, {key: value}), Config.load(scenario).set(key, value),
                   load_config(scenario, [f"{key}={toml_literal(value)}"])]
    assert all(c == configs[0] for c in configs)


def test_a_note_points_at_the_callers_line() -> None:
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        Config.load("trapezoid-rigid", {"time.t_end": 0.4})
        Config.load("trapezoid-rigid").set("time.t_end", 0.4)
    notes = [w for w in caught if issubclass(w.category, ConfigNote)]
    assert len(notes) == 2
    assert {Path(w.filename).resolve() for w in notes} == {Path(__file__).resolve()}


def test_messages_name_each_interfaces_own_words(tmp_path: Path) -> None:
    with pytest.raises(ConfigError, match=r"an override is section\.key=value"):
        Config.load("plug-flow", ["numerics.eps"])
    err = io.StringIO()
    with contextlib.redirect_stderr(err), pytest.raises(SystemExit) as code:
        main(["show", "plug-flow", "--set", "numerics.eps"])
    assert code.value.code == 2
    assert "--set: expects section.key=value" in err.getvalue()
    tiny = {"mesh.size": 0.5, "time.dt": 0.05, "time.t_end": 0.05, "time.output_times": [],
            "numerics.eps": 1e-2}
    out = tmp_path / "run"
    granflow.run("plug-flow", tiny, out=out, progress=False)
    with pytest.raises(RunDirError) as info:
        granflow.run("plug-flow", tiny, out=out, progress=False)
    assert "force=True" in str(info.value) and "--" not in str(info.value)
    assert f"granflow.resume('{out}')" in str(info.value)
    err = io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
        assert main(["run", "plug-flow", "--out", str(out), "--quiet"]) == 2
    assert "--force" in err.getvalue()


def test_reprs_are_short(tmp_path: Path) -> None:
    config = Config.load("trapezoid-rigid")
    assert len(repr(config)) < 200 and "\n" not in repr(config)
    tiny = {"mesh.size": 0.5, "time.dt": 0.05, "time.t_end": 0.05, "time.output_times": [],
            "numerics.eps": 1e-2}
    run = granflow.run("plug-flow", tiny, out=tmp_path / "run", progress=False)
    assert len(repr(run.summary)) < 400
    fields = run.fields(run.output_times[-1])
    assert len(repr(fields)) < 300 and "velocity" in repr(fields)
