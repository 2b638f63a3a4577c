"""The layers of docs/architecture.md, read from the page and checked against the code:
every import of a granflow module points to its own layer or one below, the packages import
one another without a cycle, and the engine-free packages import no finite-element engine."""

from __future__ import annotations

import ast
import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
SOURCE = ROOT / "src" / "granflow"
ENGINES = ("ngsolve", "netgen")
ENGINE_FREE = ("physics", "config", "simulation", "reference", "state")   # the page's words
# the modules of geometry/ that mesh with Netgen: sections (2D) and solids (3D)
MESHERS = ["geometry/mesh.py", "geometry/mesh3d.py"]


def page_layers() -> list[list[str]]:
    """The packages and modules of each row of the page's layer table, top to bottom."""
    text = (ROOT / "docs" / "architecture.md").read_text(encoding="utf-8")
    table = text.split("| layer | package or module | what it holds |", 1)[1]
    rows = []
    for line in table.splitlines()[2:]:
        if not line.startswith("|"):
            break
        cell = line.split("|")[2]
        rows.append([name.removesuffix("/").removesuffix(".py")
                     for name in re.findall(r"`([^`]+)`", cell)])
    return rows


LAYERS = page_layers()
RANK = {name: i for i, names in enumerate(LAYERS) for name in names}


def package(module: str) -> str:
    """granflow.io.plots -> io; granflow.cli -> cli; granflow -> __init__."""
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else "__init__"


def imported(path: Path) -> list[str]:
    """Every module the file imports, at its top or inside a function."""
    out = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.ImportFrom) and node.level == 0:
            out.append(node.module or "")
        elif isinstance(node, ast.Import):
            out += [a.name for a in node.names]
    return out


def imports() -> list[tuple[str, str, str]]:
    """(importing file, its package, imported package) for every granflow import."""
    out = []
    for path in SOURCE.rglob("*.py"):
        mine = path.relative_to(SOURCE).with_suffix("").parts[0]
        out += [(str(path.relative_to(SOURCE)), mine, package(name))
                for name in imported(path) if name.split(".")[0] == "granflow"]
    return out


def test_the_page_lists_the_layers() -> None:
    """The table is read: six layers, the application one package, the loop and the files
    below the finite elements, the checkpoint's schema on the ground floor."""
    assert len(LAYERS) == 6
    assert RANK["app"] == 0 and RANK["scenarios"] == 1
    assert RANK["fem"] < RANK["simulation"] == RANK["io"] < RANK["physics"] == RANK["state"]


def test_earlier_module_names_are_the_modules_they_became() -> None:
    """``granflow.runner``, ``granflow.cli``, ... (and the schema's earlier home) import as
    the very modules of ``granflow.app`` (a patch of one patches the other)."""
    import importlib

    from granflow.earlier_names import EARLIER

    for old, new in EARLIER.items():
        assert importlib.import_module(old) is importlib.import_module(new), old


def test_every_package_has_a_layer() -> None:
    found = {p.relative_to(SOURCE).parts[0].removesuffix(".py") for p in SOURCE.iterdir()
             if p.suffix == ".py" or (p.is_dir() and (p / "__init__.py").exists())}
    assert found <= set(RANK), found - set(RANK)


def test_imports_point_down_the_layers() -> None:
    upward = [(f, other) for f, mine, other in imports() if RANK[other] < RANK[mine]]
    assert upward == []


def test_packages_import_one_another_without_a_cycle() -> None:
    graph: dict[str, set[str]] = {}
    for _, mine, other in imports():
        if mine != other and other != "__init__":
            graph.setdefault(mine, set()).add(other)

    def reaches(start: str, goal: str, seen: set[str]) -> bool:
        for nxt in graph.get(start, ()):
            if nxt == goal or (nxt not in seen and reaches(nxt, goal, seen | {nxt})):
                return True
        return False

    cycles = [p for p in graph if reaches(p, p, {p})]
    assert cycles == []


def test_engine_free_packages_import_no_finite_element_engine() -> None:
    """physics/, config/, simulation/ and reference/ name neither NGSolve nor Netgen in any
    import; in geometry/ only the meshers do."""
    users = sorted(str(p.relative_to(SOURCE)) for p in SOURCE.rglob("*.py")
                   if any(name.split(".")[0] in ENGINES for name in imported(p)))
    assert "fem/flow.py" in users                       # the walk sees the engine's users
    assert [f for f in users if f.split("/")[0] in ENGINE_FREE] == []
    assert [f for f in users if f.startswith("geometry/")] == MESHERS


def test_engine_free_packages_import_with_the_engine_blocked() -> None:
    """Every module of those packages imports, with whatever granflow module it imports in
    turn, while any import of NGSolve or Netgen raises."""
    modules = sorted(".".join(("granflow", *p.relative_to(SOURCE).with_suffix("").parts))
                     .removesuffix(".__init__")
                     for pkg in ENGINE_FREE for p in (SOURCE / pkg).rglob("*.py"))
    script = "\n".join(["import importlib, sys",
                        *(f"sys.modules[{e!r}] = None" for e in ENGINES),
                        f"for m in {modules!r}: importlib.import_module(m)",
                        "print(len(sys.modules))"])
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                          timeout=120)
    assert done.returncode == 0, done.stderr[-2000:]
    assert len(modules) > 20


# ------------------------------------------------------------------ the page's other claims


def page_paths(heading: str) -> set[str]:
    """Every `path.py` (or `path.py: name`) named in the table under ``heading``."""
    text = (ROOT / "docs" / "architecture.md").read_text(encoding="utf-8")
    section = text.split(heading, 1)[1].split("\n## ", 1)[0]
    return {m.split(":")[0] for m in re.findall(r"`([\w/]+\.py(?:: \w+)?)`", section)}


def source_lines(pattern: str) -> list[str]:
    """file:line of every line of granflow's source that matches ``pattern``."""
    found = re.compile(pattern)
    return [f"{p.relative_to(SOURCE)}:{i}" for p in sorted(SOURCE.rglob("*.py"))
            for i, line in enumerate(p.read_text(encoding="utf-8").splitlines(), 1)
            if found.search(line)]


def test_every_home_the_page_names_exists() -> None:
    homes = page_paths("## One home for each moving part")
    assert len(homes) > 40
    assert [h for h in homes if not (SOURCE / h).is_file()] == []


def test_composite_laws_are_unwrapped_in_one_place() -> None:
    """No isinstance on a law that blends two others outside physics/composite.py (the
    hysteretic law's own module names itself)."""
    found = source_lines(r"isinstance\([^)]*(TwoMaterials|Hysteretic)")
    assert {f.split(":")[0] for f in found} <= {"physics/hysteresis.py"}


def test_only_a_kind_names_a_kind() -> None:
    """geometry.kind is compared with a kind's name nowhere: each kind's rules and builder
    are found by the registries (config/kinds.py, scenarios/registry.py)."""
    assert source_lines(r"kind ?[!=]= ?['\"](column|periodic-layer)") == []


def test_a_kind_declares_itself_from_scenarios_without_the_engine() -> None:
    """The modules of BUILT_IN that declare the kinds to the configuration import no
    finite-element engine (the package imports them first, the engine-free ones too)."""
    from granflow.scenarios import BUILT_IN

    for rules, _ in BUILT_IN:
        path = SOURCE / Path(*rules.split(".")[1:]).with_suffix(".py")
        assert not any(name.split(".")[0] in ENGINES for name in imported(path)), path


def files(pattern: str) -> set[str]:
    """The files of granflow's source with a line that matches ``pattern``."""
    return {f.split(":")[0] for f in source_lines(pattern)}


def test_a_column_is_resolved_once() -> None:
    """A run's scene (and the bed profile's file) is built from the configuration in one
    place, ``ColumnSetup.of``; the configuration's checks build their own."""
    assert files(r"\bbuild_scene\(") == {"geometry/scene.py", "scenarios/column_setup.py",
                                          "scenarios/column_geometry_rules.py"}


def test_three_questions_each_have_one_home() -> None:
    """Is the run axisymmetric: ``fem/measure.py: coordinates_of`` reads the key (beside the
    configuration's rules and the scene's check of a profile). Is there an erodible layer:
    ``column_geometry_rules.erodible`` compares the thickness with 0 (the scene builds its
    layer from the number). Is the bed the paper's: the scene decides from the profile keys
    (the geometry rules test whether one is given)."""
    rules = {"scenarios/column_rules.py", "scenarios/column_geometry_rules.py",
             "scenarios/plug_flow_rules.py", "scenarios/three_d_rules.py",
             "scenarios/slab_rules.py"}
    assert files(r"\b(geometry|geo|g)\.axisymmetric\b") <= {"fem/measure.py",
                                                             "geometry/scene.py", *rules}
    assert files(r"^[^\"'#]*erodible_thickness\s*(>|<=)\s*0\b") == {
        "scenarios/column_geometry_rules.py"}
    assert files(r"bed_profile(_file)? is (not )?None") == {
        "geometry/scene.py", "scenarios/column_geometry_rules.py"}


def test_the_flow_solver_names_no_coupling() -> None:
    """The solver and its factory hold couplings behind their protocol (``fem/coupling.py``):
    neither imports a coupling's module nor asks whether one is there; the page draws them."""
    couplings = {"granflow.fem.fluidity", "granflow.fem.augmented_lagrangian",
                 "granflow.fem.primal_dual", "granflow.fem.mobilisation_field",
                 "granflow.fem.material_share"}
    for module in ("fem/flow.py", "fem/flow_factory.py", "fem/flow_spec.py"):
        assert not couplings & set(imported(SOURCE / module)), module
    assert source_lines(r"(fluidity|augmented|dual|mobilisation)\w* is (not )?None") == [
        f for f in source_lines(r"(fluidity|augmented|dual|mobilisation)\w* is (not )?None")
        if f.split(":")[0] in {"fem/fluidity.py", "fem/augmented_lagrangian.py",
                               "fem/nonlinear.py", "fem/primal_dual.py",
                               "scenarios/fluidity.py", "scenarios/mobilisation_tracking.py",
                               "scenarios/column_discretisation.py", "scenarios/column.py",
                               "scenarios/plug_flow.py", "scenarios/slab.py",
                               "scenarios/column_remesher.py"}]
    page = (ROOT / "docs" / "architecture.md").read_text(encoding="utf-8")
    assert "## The flow solver, built from parts" in page and "build_flow" in page
