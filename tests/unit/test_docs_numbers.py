"""The numbers the documentation quotes from benchmarks/results/ are those files' numbers.

``CLAIMS`` declares each one: the page, the text around it as the page says it (``{}``
where the number stands; whitespace and line breaks do not matter), the results file, where
the number is in it, and how the page rounds it. A benchmark rerun that moves a number, or
a page edited by hand, makes this test fail until both agree again. The examples' figures
on docs/examples.md are checked to be there, one per script. The numbers of the runs the
pages show (``granflow run ...``: the default collapse's stop time and printed lines, ...)
are claimed on their fresh runs' record instead (benchmarks/docs_numbers.py,
tests/unit/test_docs_runs.py).
"""

from __future__ import annotations

import importlib.util
import json
import math
import re
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest

ROOT = Path(__file__).resolve().parents[2]
RESULTS = ROOT / "benchmarks" / "results"

Path_ = str | Callable[[Any], float]

SPEED_T = "speed_default_install/trapezoid.json"
SPEED_R = "speed_default_install/rectangle.json"
UMFPACK_T = "speed_default_install/umfpack/trapezoid.json"
EULER = "time_scheme/time_scheme.json"
TABLE1, TABLE2 = "plug_flow/table1.json", "plug_flow/table2.json"
ITERATIONS = "plug_flow/iterations.json"
INCLINE = "incline/incline.json"
ASPECT = "aspect_ratio/aspect_ratio.json"
CYLINDER = "aspect_ratio_cylinder/aspect_ratio.json"
FIRST_RUNS = "collapse/paper.json"
HYSTERESIS = "hysteresis/hysteresis.json"
REPRODUCIBILITY = "reproducibility/reproducibility.json"
MAIN_VS_3D = "collapse/main-vs-three-d.json"
MKL_MODES = "mkl_modes/mkl_modes.json"
CYL_AUTO, CYL_COMPAT = "cylinder_rest/cyl-auto.json", "cylinder_rest/cyl-compat.json"
CYL_PAIR, CYL_CREEP = "cylinder_rest/cyl-compat-vs-cyl-auto.json", "cylinder_rest/rest_creep.json"
CYL = "cylinder-erodible"


STEP_BEFORE = "layer_tracking_step/fe447ab.json"
STEP_AFTER = "layer_tracking_step/01e34ac.json"
PROFILE_BEFORE = "profile_shares/trapezoid-erodible-fe447ab.json"
PROFILE_AFTER = "profile_shares/trapezoid-erodible-01e34ac.json"
TRACKING_PAIR = "speed_targets/tracking/speed_targets.json"
TRACKING_BASE = "speed_targets/tracking-baseline/speed_targets.json"
SLOPE22_RUN = "slope22_steps/progress-slow.json"
SLOPE22_PROFILE = "slope22_steps/profile-slow.json"
SLOPE22_PAIR = "slope22_steps/slope22_steps.json"


def _step(at: str, part: str = "") -> Callable[[Any], float]:
    """benchmarks/layer_tracking_step.py: a part of the tracking's step (ms) at time AT, or
    the whole step."""
    return lambda d: d["states"][at]["costs_ms"][part] if part else d["states"][at]["step_ms"]


def _share(category: str) -> Callable[[Any], float]:
    """A category's share of a py-spy profile (benchmarks/profile_shares.py's names)."""
    return lambda d: d["shares"][category]


def _surfaces(reduce: str) -> Callable[[Any], float]:
    """The two MKL modes' cylinders: the largest mean or max free-surface distance (m)."""
    return lambda d: max(gap[reduce] for gap in d[CYL]["free_surfaces"].values())


def _creep(mode: str, key: str) -> Callable[[Any], float]:
    """A figure of the cylinder's rest creep (benchmarks/rest_creep.py) in one MKL mode."""
    return lambda d: d[f"cyl-{mode}/{CYL}"][key]


def _window_speed(mode: str, t0: float) -> Callable[[Any], float]:
    """The largest speed (m/s) in the creep window starting at ``t0``."""
    return lambda d: next(w["max_speed_max_m_s"] for w in d[f"cyl-{mode}/{CYL}"]["windows"]
                          if math.isclose(w["t0"], t0))


def _compatible_extra(case: str) -> Callable[[Any], float]:
    """The fraction of processor time the reproducible MKL kernels add to ``case``."""
    return lambda data: data[case]["ratio_compatible_to_auto"]["cpu_s"] - 1


PACKING = "packing/validation.json"
PACKING_COST = "packing/cost.json"


def _step_cost(case: str) -> Callable[[Any], float]:
    """The median over the pairs of a case's processor seconds per step."""
    def value(data: Any) -> float:
        costs = sorted(p[case]["cpu_s"] / p[case]["steps"] for p in data["pairs"])
        middle = len(costs) // 2
        return costs[middle] if len(costs) % 2 else (costs[middle - 1] + costs[middle]) / 2
    return value
PLANE_14 = "three_d_collapse/plane_strain_h0.014.json"
WALLS = "three_d_krylov/walls/strong_walls.json"
WALLS_PAIR = "three_d_krylov/walls/3d-penalty-vs-3d-strong.json"
WALLS_REST = "three_d_krylov/walls/strong_walls_rest.json"
WALLS_REST_PAIR = "three_d_krylov/walls/3d-rest-penalty-vs-3d-rest-strong.json"
WALLS_2D = "three_d_krylov/walls/2d-main-13e348f-vs-2d-strong-walls.json"
KRYLOV_FRONT_20 = "three_d_krylov/column_front_h0.02_dt0.0001_n1.json"
KRYLOV_EXACT_20 = "three_d_krylov/column_flowing_h0.02_dt0.0001_exactu_n1.json"
KRYLOV_FLOWING_14 = "three_d_krylov/column_flowing_h0.014_dt0.0001_n1.json"
KRYLOV_REST_04 = "three_d_krylov/column_rest_h0.04_dt0.0001_n1.json"
KRYLOV_PLUG = "three_d_krylov/plug_flowing_dt0.025_n1.json"
SPLIT_REST_14 = "three_d_krylov/fieldsplit_rest_h0.014.json"
SPLIT_REST_10 = "three_d_krylov/fieldsplit_rest_h0.01.json"
RANKS = "three_d_krylov/fieldsplit_ranks_{}_h{}_n{}.json"


def _ranks_apart(key: str) -> Callable[[Any], float]:
    """|two ranks / one rank - 1| of a fieldsplit record at rest at 18,192 unknowns."""
    one = json.loads((RESULTS / RANKS.format("rest", "0.014", 1)).read_text())
    return lambda data: abs(data[key] / one[key] - 1)


SPLIT_COLLAPSE = "three_d_collapse/rest_h0.04_n1_fieldsplit_t0.03.json"
SPLIT_COLLAPSE_2 = "three_d_collapse/rest_h0.04_n2_fieldsplit_t0.03.json"
RIGID_2 = "three_d_krylov/fieldsplit_ranks_flexible_rigid_{}_h0.02_n2.json"
RIGID = "three_d_krylov/fieldsplit_ranks_{}_{}_h0.02_n1.json"


SCALED = "three_d_fieldsplit/fieldsplit_ranks_{}_{}_h{}_n1.json"
SCALED_TABLE = "three_d_fieldsplit/table.json"
SCALED_N1 = "three_d_fieldsplit/rest_h0.04_n1_fieldsplit_t0.03.json"
SCALED_N2 = "three_d_fieldsplit/rest_h0.04_n2_fieldsplit_t0.03.json"
SCALED_N1_01 = "three_d_fieldsplit/rest_h0.04_n1_fieldsplit_t0.1.json"
SCALED_N2_01 = "three_d_fieldsplit/rest_h0.04_n2_fieldsplit_t0.1.json"


COST = "three_d_fieldsplit/cost.json"
COST_LSC = "three_d_fieldsplit/lsc/rest_h0.04_n1_fieldsplit_t0.03.json"
COST_LSC_2 = "three_d_fieldsplit/lsc/rest_h0.04_n2_fieldsplit_t0.03.json"
DIRECT_SOLVERS = ("umfpack", "pardiso")
FIELDSPLIT_SOLVERS = ("selfp-gamg-flexible", "lsc-gamg-flexible")


def _cost(solvers: tuple[str, ...], key: str, pick: Callable[[list[float]], float] = min,
          index: int | None = None) -> Callable[[Any], float]:
    """``pick`` of cost.json's ``key`` over the states and ``solvers`` (an entry per size
    unless ``index`` picks one size)."""
    def value(d: Any) -> float:
        found = []
        for entry in d["states"].values():
            for solver in solvers:
                v = entry["solvers"][solver][key]
                found += v if isinstance(v, list) and index is None else [
                    v[index] if isinstance(v, list) else v]
        return pick(found)
    return value


def _lsc_over(other: str, pick: Callable[[list[float]], float]) -> Callable[[Any], float]:
    """``pick`` of LSC's time per solve over another solver's, the two largest sizes."""
    return lambda d: pick([e["solvers"]["lsc-gamg-flexible"]["cpu_s"][i]
                           / e["solvers"][other]["cpu_s"][i]
                           for e in d["states"].values() for i in (-2, -1)])


def _check_record(state: str) -> Any:
    return json.loads((RESULTS / f"three_d_fieldsplit/check_{state}_h0.008.json").read_text())


def _check(solver: str, pick: Callable[[list[float]], float]) -> Callable[[Any], float]:
    """``pick`` of measured / fitted time per solve at the size measured apart."""
    return lambda d: pick([c["cpu_s"] / c["fit_s"] for c in d["checks"]
                           if c["solver"] == solver])


def _lsc_collapse_over(name: str) -> Callable[[Any], float]:
    return lambda d: d["cpu_s"] / _scaled_collapse(name)["cpu_s"]


def _cross(solver: str, ranks: int, pick: Callable[[list[float]], float]) -> Callable[[Any], float]:
    return lambda d: pick([e["crossover"][solver][str(ranks)] for e in d["states"].values()])


def _within(variant: str, key: str, end: int) -> Callable[[Any], float]:
    """One end of a range of three_d_fieldsplit/table.json's ``within_1e-6``."""
    return lambda d: d["within_1e-6"][variant][key][end]


def _scaled_collapse(name: str) -> Any:
    return json.loads((RESULTS / f"three_d_fieldsplit/rest_h0.04_{name}.json").read_text())


def _scaled_ratio(other: str) -> Callable[[Any], float]:
    """A scaled fieldsplit collapse's processor time over another run's (``_scaled_collapse``)."""
    return lambda d: d["cpu_s"] / _scaled_collapse(other)["cpu_s"]


def _scaled_apart(key: str, other: str) -> Callable[[Any], float]:
    """|a scaled fieldsplit collapse's front - another run's| (m)."""
    return lambda d: abs(d[key] - _scaled_collapse(other)[key])


TIMING_NAMES = ("flexible", "lsc-gamg-flexible", "cahouet-chabard")
STATES = ("rest", "flowing", "front")


def _timing(kind: str, state: str) -> dict[str, float]:
    """Processor seconds of a scaled variant's solve at 18,192 unknowns (timing/)."""
    return json.loads((RESULTS / "three_d_fieldsplit/timing" / (
        f"fieldsplit_ranks_{kind}_rigid_scaled_{state}_h0.014_n1.json")).read_text(
        ))["cpu_s_per_rank"][0]


def _lsc_over_selfp(d: Any) -> list[float]:
    return [_timing("lsc-gamg-flexible", s)["solve"] / _timing("flexible", s)["solve"]
            for s in ("rest", "flowing", "front")]


def _over_direct(d: Any) -> list[float]:
    return [t["solve"] / t["direct"] for k in TIMING_NAMES
            for t in (_timing(k, s) for s in STATES)]


def _left_steps(state: str) -> int:
    """The left-preconditioned fieldsplit's steps without the rigid modes, 5,414 unknowns."""
    return json.loads((RESULTS / RANKS.format(state, "0.02", 1)).read_text())["steps"]


SPLIT_SIZES = {"lsc-lu": ("0.04", "0.02", "0.014"), "selfp-lu": ("0.04", "0.02", "0.014"),
               "mass-lu": ("0.04", "0.02", "0.014"),
               "lsc-gamg": ("0.04", "0.02", "0.014", "0.01"),
               "selfp-gamg": ("0.04", "0.02", "0.014", "0.01")}
PLANE_20 = "three_d_collapse/plane_strain_h0.02.json"
PLANE_20_OLD = "three_d_collapse/plane_strain_h0.02_85514c0.json"   # the end faces mislabelled
PLANE_MU_20 = "three_d_collapse/plane_strain_h0.02_mu-i.json"
PLANE_MU_14 = "three_d_collapse/plane_strain_h0.014_mu-i.json"
PLANE_TRAP_30 = "three_d_collapse/plane_strain_h0.03_trapezoid.json"
PLANE_TRAP_20 = "three_d_collapse/plane_strain_h0.02_trapezoid.json"
REST_1, REST_2 = "three_d_collapse/rest_h0.04_n1.json", "three_d_collapse/rest_h0.04_n2.json"
REST_1_OLD = "three_d_collapse/rest_h0.04_n1_ae713bc.json"    # the earlier records
REST_1_323 = "three_d_collapse/rest_h0.04_n1_323ba64.json"   # before the face labels
REST_2_OLD = "three_d_collapse/rest_h0.04_n2_ae713bc.json"
REST_2D = "three_d_collapse/rest2d_h0.04.json"


def _order(coarse: str, fine: Any, key: str) -> float:
    """The observed order of a gap between a record at a coarser mesh.size and ``fine``."""
    def gap(data: Any) -> float:
        if key.startswith("surface_distance"):
            return abs(data["surface_distance_behind_front_max_m"]["0.1"])
        return abs(data[key])
    other = json.loads((RESULTS / coarse).read_text())
    return math.log(gap(other) / gap(fine)) / math.log(other["size"] / fine["size"])


def _split_cpu(data: Any, variant: str) -> float:
    """A fieldsplit variant's processor seconds, set-up and solve."""
    cpu = next(r["cpu_s"] for r in data if r["variant"] == variant)
    return cpu["setup"] + cpu["solve"]


def _own(function: str) -> Callable[[Any], float]:
    """The own processor seconds of a profiled function of a run to rest."""
    return lambda data: next(r["own_s"] for r in data["profile"] if function in r["function"])


def _apart(key: str, scale: float = 100.0) -> Callable[[Any], float]:
    """|two ranks / one rank - 1| of a run-to-rest figure, in %."""
    one = json.loads((RESULTS / "three_d_collapse/rest_h0.04_n1.json").read_text())
    return lambda data: scale * abs(data[key] / one[key] - 1)


CHANNEL = "three_d_collapse/channel_h0.04.json"
CHANNEL_OLD = "three_d_collapse/channel_h0.04_ea5e448.json"    # before the side-wall landing
CHANNEL_7A = "three_d_collapse/channel_h0.04_7a002f4.json"    # before the face labels
CREEP, CREEP_OLD = "three_d_collapse/creep.json", "three_d_collapse/creep_ae713bc.json"
PROBE = "three_d_collapse/creep_ae713bc_probe.json"
RUN_3D, RUN_2D = "channel3d_h0.04", "channel2d_h0.04"
SLOPE19 = "three_d_collapse/channel_h0.04_slope19.json"
SLOPE19_OLD = "three_d_collapse/channel_h0.04_slope19_b6a2d0e.json"   # before the face labels
SLOPE19_CROSSING = "three_d_collapse/channel_h0.04_slope19_crossing.json"   # before landing
ERODIBLE_19_RUNOUT = json.loads((RESULTS / "erosion_slopes/erosion_slopes.json").read_text())[
    "side-walls/rectangle-0mm-19"]["runout_m"]


def _surfaces_max(side: str, key: str) -> Callable[[Any], float]:
    """The largest ``key`` of the channel's 3D ``side`` surface against 2D, any time."""
    return lambda d: max(g[side][key] for g in d["surfaces"].values())


def _snapshot(run: str, t: float, key: str | Callable[[Any], float],
              scale: float = 1.0) -> Callable[[Any], float]:
    """A creep record's snapshot figure at the snapshot nearest ``t`` (s)."""
    def value(data: Any) -> float:
        row = min(data[run]["snapshots"], key=lambda r: abs(r["t"] - t))
        return scale * (key(row) if callable(key) else row[key])
    return value


def _last(run: str, key: str) -> Callable[[Any], float]:
    """A creep record's figure at its last snapshot."""
    return lambda data: data[run]["snapshots"][-1][key]


def _at(key: str, t: str) -> Callable[[Any], float]:
    """A plane-strain record's ``key`` at output time ``t`` (its keys hold dots)."""
    return lambda data: data[key][t]


SLAB, SLAB_FLUIDITY = "slab/slab.json", "slab/slab_fluidity.json"
BED_MODELS = "bed_models/bed_models.json"


def _slab_ratio(variant: str, slope: int) -> Callable[[Any], float]:
    """The slab's distance over the 5 mm layer over its distance on the bed alone."""
    def ratio(data: Any) -> float:
        return (data[f"{variant}|5mm|{slope}"]["slab_distance_m"]
                / data[f"{variant}|0mm|{slope}"]["slab_distance_m"])
    return ratio


ETA_STUDY = "erosion_slopes_eta/erosion_slopes.json"
ETA_VARIANT = "glass-beads-no-slip-small-eta/rectangle"


def _flat(name: str, key: str) -> Callable[[Any], float]:
    """A level-bed run's figure (its name holds a dot: eta0.01)."""
    return lambda data: data["flat"][name][key]


def _study(he: str, slope: int, key: str) -> Callable[[Any], float]:
    """A row of the erosion study on the no-slip bed with eta = 0.01 (he in mm, "0" rigid)."""
    return lambda data: data[f"{ETA_VARIANT}-{he}mm-{slope}"][key]


def _study_ratio(he: str, slope: int) -> Callable[[Any], float]:
    """The row's front at its end over its rigid twin's (its runout once both rest)."""
    return lambda data: (data[f"{ETA_VARIANT}-{he}mm-{slope}"]["runout_m"]
                         / data[f"{ETA_VARIANT}-0mm-{slope}"]["runout_m"])


def _study_gain(he: str, slope: int, t: str) -> Callable[[Any], float]:
    """The row's front minus its rigid twin's at time ``t`` (m)."""
    return lambda data: (data[f"{ETA_VARIANT}-{he}mm-{slope}"]["front_history"][t]
                         - data[f"{ETA_VARIANT}-0mm-{slope}"]["front_history"][t])


WALLS_STUDY = "erosion_slopes_walls/erosion_slopes.json"
WALLS_STUDY_316 = "erosion_slopes_walls/erosion_slopes_316f20f.json"   # before the fold fixes
FOUR = "glass-beads-no-slip-small-eta-walls/rectangle-5mm-0-4cells"   # four cells across


def _four(key: str) -> Callable[[Any], float]:
    """The level row over 5 mm with four cells across the layer, in the channel."""
    return lambda data: data[FOUR][key]


def _four_gain(t: str | None) -> Callable[[Any], float]:
    """Its front minus the rigid twin's at ``t`` (at rest: None), in mm."""
    def gain(data: Any) -> float:
        rigid = data[f"{WALLS_VARIANT}-0mm-0"]
        if t is None:
            return 1e3 * (data[FOUR]["runout_m"] - rigid["runout_m"])
        return 1e3 * (data[FOUR]["front_history"][t] - rigid["front_history"][t])
    return gain
WALLS_VARIANT = "glass-beads-no-slip-small-eta-walls/rectangle"
NO_WALLS = json.loads((RESULTS / ETA_STUDY).read_text())
WALLS_DATA = json.loads((RESULTS / WALLS_STUDY).read_text())


def _at_3(row: dict) -> dict:
    """A row as it stood at the study's 3 s: a row carried further keeps it (``earlier``)."""
    return row.get("earlier", {}).get("3", row)


def _walls(he: str, slope: int, key: str) -> Callable[[Any], float]:
    """A row of the study in the 10 cm channel (he in mm, "0" rigid) at 3 s."""
    return lambda data: _at_3(data[f"{WALLS_VARIANT}-{he}mm-{slope}"])[key]


def _walls_gain(slope: int, t: str | None, rows: str = "walls") -> Callable[[Any], float]:
    """The 5 mm row's front minus its rigid twin's at ``t`` (at rest: None), in mm, of the
    study in the channel or (``rows`` = "none") of the one without walls."""
    def gain(data: Any) -> float:
        data, variant = (data, WALLS_VARIANT) if rows == "walls" else (NO_WALLS, ETA_VARIANT)
        layer, rigid = (_at_3(data[f"{variant}-{he}mm-{slope}"]) for he in ("5", "0"))
        if t is None:
            return 1e3 * (layer["runout_m"] - rigid["runout_m"])
        return 1e3 * (layer["front_history"][t] - rigid["front_history"][t])
    return gain


def _walls_ratio(data: Any) -> float:
    """The level row's runout over its rigid twin's, in the channel."""
    return data[f"{WALLS_VARIANT}-5mm-0"]["runout_m"] / data[f"{WALLS_VARIANT}-0mm-0"]["runout_m"]


def _walls_ratio_at(slope: int) -> Callable[[Any], float]:
    """The 5 mm row's front over its rigid twin's at the end (by 3 s), in the channel."""
    return lambda data: (_at_3(data[f"{WALLS_VARIANT}-5mm-{slope}"])["runout_m"]
                         / _at_3(data[f"{WALLS_VARIANT}-0mm-{slope}"])["runout_m"])


def _fronts_row(label: str, slope: int, clock: tuple[str | None, ...]) -> list[tuple]:
    """One claim a cell of the fronts table's row ``label`` in the channel: the 5 mm row's
    front minus its rigid twin's at each time of ``clock`` (None: at rest; "-": no cell's
    number), in mm."""
    cells = ["-" if t == "-" else f"{_walls_gain(slope, t)(WALLS_DATA):+.0f}" for t in clock]
    return [("docs/erosion.md",
             "| " + " | ".join([label, *cells[:i], "{}", *cells[i + 1:]]) + " |",
             WALLS_STUDY, _walls_gain(slope, t), "+.0f", 1)
            for i, t in enumerate(clock) if t != "-"]


def _beyond_footprint(slope: int) -> Callable[[Any], float]:
    """The share of the displaced layer that started beyond the column's footprint."""
    return lambda data: 1 - data[f"{WALLS_VARIANT}-5mm-{slope}"][
        "displaced_from_under_column_share"]


PACKED_LAYERS = [f"{law}/{bed}+small-eta+{packing}-layer"
                 for law in ("drucker-prager", "glass-beads", "hysteretic", "nonlocal")
                 for bed in ("no-slip", "material-bed") for packing in ("loose", "dense")]


def _packed_extreme(key: str, reduce: Callable[..., float]) -> Callable[[Any], float]:
    """The smallest or largest ``key`` of the runs over a loose or a dense layer."""
    return lambda data: reduce(data[f"{v}|5mm|{s}"][key] for v in PACKED_LAYERS
                               for s in (0, 10, 16, 19, 22))


def _loose_over_dense(reduce: Callable[..., float]) -> Callable[[Any], float]:
    """The slab's distance over the loose layer over that over the dense one, the smallest
    or largest but the hysteretic law's."""
    def value(data: Any) -> float:
        return reduce(data[f"{law}/{bed}+small-eta+loose-layer|5mm|{s}"]["slab_distance_m"]
                      / data[f"{law}/{bed}+small-eta+dense-layer|5mm|{s}"]["slab_distance_m"]
                      for law in ("drucker-prager", "glass-beads", "nonlocal")
                      for bed in ("no-slip", "material-bed") for s in (0, 10, 16, 19, 22))
    return value


def _against_paper_model(name: str) -> Callable[[Any], float]:
    """A level-bed run's runout against Drucker-Prager's on the Coulomb bed, |ratio - 1|."""
    def relative(data: Any) -> float:
        shape = name.split("-")[0]
        reference = data["flat"][f"{shape}-drucker-prager-coulomb"]["runout_m"]
        return abs(data["flat"][name]["runout_m"] / reference - 1)
    return relative


def _spreading_cut(shape: str, length: float) -> Callable[[Any], float]:
    """The share of the no-slip run's spreading beyond the initial length ``length`` (m)
    that the 10 cm channel's walls take, eta = 0.01."""
    def cut(data: Any) -> float:
        runs = data["flat"]
        free = runs[f"{shape}-glass-beads-no-slip-eta0.01"]["runout_m"] - length
        walls = runs[f"{shape}-glass-beads-no-slip-eta0.01-walls0.1"]["runout_m"] - length
        return 1 - walls / free
    return cut


def _walls_cut(scenario: str, length: float) -> Callable[[Any], float]:
    """The share of the paper's model's spreading beyond ``length`` (m) that the 10 cm
    channel's walls take (benchmarks/side_walls.py)."""
    def cut(data: Any) -> float:
        runs = {r["case"]: r["runout_m"] for r in data if r["scenario"] == scenario}
        return 1 - (runs["side walls"] - length) / (runs["no side walls"] - length)
    return cut


def _largest_surface_gap(data: Any) -> float:
    """The largest distance (m) between two checkouts' free surfaces, any run, any time."""
    return max(gap["max_m"] for run in data.values() for gap in run["free_surfaces"].values())
INTERFACE = "interface_resolution/interface_resolution.json"


def _path_run(setting: str, key: str, member: str | None = None) -> Callable[[Any], float]:
    """A setting's value in the reproducibility record (its keys hold dots and spaces)."""
    def value(data: Any) -> float:
        entry = data["settings"][setting][key]
        return entry if member is None else entry[member]
    return value


def _rectangles_vs(law: str) -> Callable[[Any], float]:
    """How much longer (in %) than a published law the rectangles run out at a = 4."""
    def value(d: Any) -> float:
        i = d["a"].index(4.0)
        return 100 * (d["normalised_runout"][i] / d["published_runout"][law][i] - 1)
    return value


def _cylinders(select: Callable[[float], bool], quantity: str = "runout") -> Callable:
    """Relative gaps (%) of the cylinders to Lube's law, or their final heights."""
    def values(d: Any) -> list[float]:
        if quantity == "height":
            return [h for a, h in zip(d["a"], d["final_height"], strict=True) if select(a)]
        return [100 * (r / lube - 1) for a, r, lube in zip(
            d["a"], d["normalised_runout"], d["lube_2004_runout"], strict=True) if select(a)]
    return values


ERODIBLE_SPEED = "erodible_speed/erodible_speed.json"


def _stop(comparison: str, run: str, which: int) -> Callable[[Any], float]:
    """A run's rest-rule stop time in a comparison of two codes (0: before, 1: after)."""
    return lambda d: d[comparison][run]["counts"]["stop_time_s"][which]


def _stop_change(comparison: str, run: str) -> Callable[[Any], float]:
    """How much (in %) a run's rest-rule stop time moved in a comparison."""
    return lambda d: 100 * (_stop(comparison, run, 1)(d) / _stop(comparison, run, 0)(d) - 1)


CLAIMS: list[tuple[str, str, str, Path_, str, float]] = [
    # page, text, results file, JSON path (or a function of the JSON), format, scale
    # --- the paper's algorithm (benchmarks/speed.py case A) and the fast path (B)
    ("README.md", "stops the trapezoid at {} s (paper 0.86 s)", SPEED_T, "A.stop_time_s",
     ".3f", 1),
    ("README.md", "with a runout of {} m; granflow's default", SPEED_T, "A.runout_m", ".3f", 1),
    ("README.md", "m, {} times faster", SPEED_T, "speedup", ".1f", 1),
    ("README.md", "The rectangle stops at {} s", SPEED_R, "A.stop_time_s", ".2f", 1),
    ("docs/verification.md", "| stop time (every cell below 1 mm/s) | {} s (paper 0.86 s)",
     SPEED_T, "A.stop_time_s", ".4f", 1),
    ("docs/verification.md", "s (paper \"around 0.92 s\") |\n| runout | {} m", SPEED_T,
     "A.runout_m", ".4f", 1),
    ("docs/verification.md", "| 0.5951 s (paper \"around 0.92 s\")", SPEED_R,
     "A.stop_time_s", ".4f", 1),
    ("docs/verification.md", "| {} s (paper \"around 0.92 s\")", SPEED_R, "A.stop_time_s",
     ".4f", 1),
    ("docs/verification.md", "| runout | 0.6633 m | {} m |", SPEED_R, "A.runout_m", ".4f", 1),
    ("docs/verification.md", "| the paper: 0.86 s | - | {} s |", SPEED_T, "A.stop_time_s",
     ".3f", 1),
    ("docs/verification.md", "about 0.6 s | - | {} s |", SPEED_R, "A.stop_time_s", ".3f", 1),
    ("docs/user_guide.md", "It stops the trapezoid at {} s", SPEED_T, "A.stop_time_s",
     ".4f", 1),
    ("docs/user_guide.md", "with a runout of {} m and the rectangle", SPEED_T, "A.runout_m",
     ".4f", 1),
    ("docs/user_guide.md", "and the rectangle at {} s", SPEED_R, "A.stop_time_s", ".4f", 1),
    ("docs/user_guide.md", "s and {} m (`benchmarks/results/speed_default_install/`",
     SPEED_R, "A.runout_m", ".4f", 1),
    ("docs/user_guide.md", "(trapezoid {} s and", FIRST_RUNS, "trapezoid-rigid.stop_time_s",
     ".3f", 1),
    ("docs/user_guide.md", "s and {} m, `benchmarks/results/collapse/paper.json`",
     FIRST_RUNS, "trapezoid-rigid.runout_m", ".3f", 1),
    ("docs/performance.md", "{} steps, 1,786 nonlinear iterations", SPEED_T, "B.steps",
     ",d", 1),
    ("docs/performance.md", "{} nonlinear iterations, 3,701", SPEED_T,
     "B.nonlinear_iterations", ",d", 1),
    ("docs/performance.md", "{} linear solves, 4 remeshes", SPEED_T, "B.linear_solves",
     ",d", 1),
    ("docs/performance.md", "at rest from {} s with a runout", SPEED_T, "B.stop_time_s",
     ".4f", 1),
    ("docs/performance.md", "with a runout of {} m; a time loop", SPEED_T, "B.runout_m",
     ".4f", 1),
    ("docs/performance.md", "a time loop of {} s,", SPEED_T, "B.wall_time_s", ".1f", 1),
    ("docs/performance.md", "{} s for the whole process", SPEED_T,
     "B_process_wall_time_median_s", ".1f", 1),
    ("docs/performance.md", "case A below, {} times slower", SPEED_T, "speedup", ".1f", 1),
    ("docs/performance.md", "UMFPACK stopped at {} s", UMFPACK_T, "B.stop_time_s", ".4f", 1),
    ("docs/performance.md", "s with {} m (below)", UMFPACK_T, "B.runout_m", ".4f", 1),
    # --- the fast path against a reference converged in time
    ("README.md", "within {} mm on average", EULER,
     "runs.implicit-euler.against_reference.surface_mean_m", ".2f", 1000),
    ("README.md", "and {} mm at most of a reference", EULER,
     "runs.implicit-euler.against_reference.surface_max_m", ".1f", 1000),
    ("docs/verification.md", "stop time 2 %; runout 5 mm | {} mm,", EULER,
     "runs.implicit-euler.against_reference.surface_mean_m", ".2f", 1000),
    ("docs/verification.md", "mm, {} mm; 0.25 %", EULER,
     "runs.implicit-euler.against_reference.surface_max_m", ".2f", 1000),
    ("docs/verification.md", "mm; {} %; 1.6 mm | pass", EULER,
     "runs.implicit-euler.against_reference.stop_time_rel", ".2f", 100),
    ("docs/verification.md", "%; {} mm | pass", EULER,
     "runs.implicit-euler.against_reference.runout_m", ".1f", 1000),
    # --- the plug flow
    ("README.md", "below the paper's error (ratios {}–", TABLE1, "min:results[eps!=0.01].ratio",
     ".2f", 1),
    ("README.md", "–{}), Table 2", TABLE1, "max:results[eps!=0.01].ratio", ".2f", 1),
    ("README.md", "Table 2 (moving mesh) at {}–", TABLE2, "min:results.ratio", ".2f", 1),
    ("README.md", "–{} of the paper's errors", TABLE2, "max:results.ratio", ".2f", 1),
    ("docs/verification.md", "| {}–0.68 × the paper's error | pass", TABLE1,
     "min:results[eps!=0.01].ratio", ".2f", 1),
    ("docs/verification.md", "0.09–{} × the paper's error | pass", TABLE1,
     "max:results[eps!=0.01].ratio", ".2f", 1),
    ("docs/verification.md", "| {}–0.41 × the paper's error;", TABLE2, "min:results.ratio",
     ".2f", 1),
    ("docs/verification.md", "0.08–{} × the paper's error;", TABLE2, "max:results.ratio",
     ".2f", 1),
    ("docs/verification.md", "volume errors {} to 5.9e-7", TABLE2, "min:results.volume_error",
     ".1e", 1),
    ("docs/verification.md", "volume errors 1.1e-8 to {} | pass", TABLE2,
     "max:results.volume_error", ".1e", 1),
    ("docs/verification.md", "| {}, 2,917, 4,859, 5,064 |", ITERATIONS,
     "[eps=0.01].iterations", ",d", 1),
    ("docs/verification.md", "| 811, {}, 4,859, 5,064 |", ITERATIONS,
     "[eps=0.0001].iterations", ",d", 1),
    ("docs/verification.md", "| 811, 2,917, {}, 5,064 |", ITERATIONS,
     "[eps=1e-06].iterations", ",d", 1),
    ("docs/verification.md", "| 811, 2,917, 4,859, {} |", ITERATIONS,
     "[eps=1e-08].iterations", ",d", 1),
    # --- the incline
    ("README.md", "(second order, {} at 32 cells)", INCLINE,
     "[case=mu-i 23 deg&cells=32].error_exact", ".1e", 1),
    ("README.md", "holds the parabola to {}.", INCLINE,
     "max:[case=drucker-prager 25 deg].error_exact", ".0e", 1),
    ("docs/verification.md", "| {} at 32 cells, second order | pass", INCLINE,
     "[case=mu-i 23 deg&cells=32].error_exact", ".1e", 1),
    ("docs/verification.md", "| 1 % (tests) | {} | pass", INCLINE,
     "max:[case=drucker-prager 25 deg].error_exact", ".0e", 1),
    # --- the aspect-ratio studies
    ("README.md", "below both at a = 0.5), {}–", ASPECT,
     _rectangles_vs("Lajeunesse et al. 2005"), ".0f", 1),
    ("README.md", "–{} % longer at a = 4", ASPECT, _rectangles_vs("Lube et al. 2005"),
     ".0f", 1),
    ("docs/verification.md", "at a = 0.5; {}–38 % longer", ASPECT,
     _rectangles_vs("Lajeunesse et al. 2005"), ".0f", 1),
    ("docs/verification.md", "–{} % longer at a = 4 | differs", ASPECT,
     _rectangles_vs("Lube et al. 2005"), ".0f", 1),
    ("README.md", "run out within {} % of Lube", CYLINDER,
     lambda d: max(abs(x) for x in _cylinders(lambda a: 0.9 < a < 2.1)(d)), ".1f", 1),
    ("docs/verification.md", "| Lube et al. (2004) | - | within {} % | agrees", CYLINDER,
     lambda d: max(abs(x) for x in _cylinders(lambda a: 0.9 < a < 2.1)(d)), ".1f", 1),
    ("README.md", "level off at {}–0.79 r0", CYLINDER,
     lambda d: min(_cylinders(lambda a: a > 1.9, "height")(d)), ".2f", 1),
    ("README.md", "level off at 0.74–{} r0", CYLINDER,
     lambda d: max(_cylinders(lambda a: a > 1.9, "height")(d)), ".2f", 1),
    ("docs/verification.md", "| {}–0.79 r0 | agrees", CYLINDER,
     lambda d: min(_cylinders(lambda a: a > 1.9, "height")(d)), ".2f", 1),
    ("docs/verification.md", "| 0.74–{} r0 | agrees", CYLINDER,
     lambda d: max(_cylinders(lambda a: a > 1.9, "height")(d)), ".2f", 1),
    ("README.md", "(a^{} against a^(1/2))", CYLINDER,
     lambda d: d["fits"]["runout_a>=1.7"]["exponent"], ".2f", 1),
    ("docs/verification.md", "| a^{} | differs", CYLINDER,
     lambda d: d["fits"]["runout_a>=1.7"]["exponent"], ".2f", 1),
    ("README.md", "(a = 3 to 6) run out {}–", CYLINDER,
     lambda d: min(_cylinders(lambda a: a > 2.9)(d)), ".0f", 1),
    ("README.md", "–{} % further", CYLINDER, lambda d: max(_cylinders(lambda a: a > 2.9)(d)),
     ".0f", 1),
    # --- the hysteretic friction on the short collapse (benchmarks/hysteresis.py)
    ("docs/verification.md", "| hysteretic (defaults) | 163 | 317 | {} |", HYSTERESIS,
     "hysteretic.mobilised_fraction_mean", ".3f", 1),
    ("docs/verification.md", "| constant friction | 163 | 313 | - | {} |", HYSTERESIS,
     lambda d: d["constant"]["front_x_0.1_m"], ".1f", 1e3),
    ("docs/verification.md", "| h = 0.01 m | 649 | 319 | {} |", HYSTERESIS,
     lambda d: d["mesh"]["levels"][-1]["mobilised_fraction_mean"], ".3f", 1),
    ("docs/verification.md", "| h = 0.01 m, constant | 641 | 319 | - | {} |", HYSTERESIS,
     lambda d: d["mesh_constant"]["levels"][-1]["front_x_0.1_m"], ".1f", 1e3),
    ("docs/verification.md", "| dt = 1.25e-4 s | 149 | 2402 | {} |", HYSTERESIS,
     lambda d: d["dt"]["levels"][-1]["mobilised_fraction_mean"], ".3f", 1),
    ("docs/verification.md", "| tau = 0.0025 s | 162 | 313 | {} |", HYSTERESIS,
     lambda d: d["tau"]["levels"][-1]["mobilised_fraction_mean"], ".3f", 1),
    ("docs/verification.md", "creep) and at most at {} 1/s", HYSTERESIS,
     "threshold.slow_q99_max", ".3f", 1),
    ("docs/model.md", "shear at most at {} 1/s", HYSTERESIS, "threshold.slow_q99_max",
     ".3f", 1),
    # --- the static/flowing interface's resolution (benchmarks/interface_resolution.py)
    ("docs/outputs.md", "(cells of {} cm) the contour", INTERFACE, "mesh_size_m", ".1f", 100),
    ("docs/outputs.md", "draws lies {} mm on average", INTERFACE,
     "vertex_speed.mean_distance_m", ".1f", 1000),
    ("docs/outputs.md", "on average and {} mm at most", INTERFACE,
     "vertex_speed.max_distance_m", ".1f", 1000),
    ("docs/outputs.md", "which jumps by up to {} mm between", INTERFACE,
     "field_level_largest_jump_m", ".1f", 1000),
    ("docs/outputs.md", "between verticals {} mm apart", INTERFACE, "station_spacing_m",
     ".1f", 1000),
    ("docs/outputs.md", "default collapse at t = {} s (cells", INTERFACE, "t", ".1f", 1),
    ("docs/performance.md", "no output times: steps, iterations | 955, {} |", REPRODUCIBILITY,
     _path_run("default", "default_collapse", "iterations"), ",d", 1),
    ("docs/performance.md", "| 955, 1,756 | 955, {} |", REPRODUCIBILITY,
     _path_run("COMPATIBLE", "default_collapse", "iterations"), ",d", 1),
    ("docs/performance.md", "cylinder / rectangle | 4.4e-7 / {} |", REPRODUCIBILITY,
     _path_run("default", "rectangle-rigid floor 0.001", "max_speed"), ".1e", 1),
    ("docs/performance.md", "| 5.7e-7 / {} |", REPRODUCIBILITY,
     _path_run("COMPATIBLE", "rectangle-rigid floor 0.001", "max_speed"), ".1e", 1),
    ("docs/performance.md", "| 3.19e-7 / 8.19e-8 | 3.19e-7 / {} |", REPRODUCIBILITY,
     _path_run("COMPATIBLE", "rectangle-rigid floor 1e-07", "max_speed"), ".2e", 1),
    ("docs/performance.md", "test_erodible.py) | {} / 0.41625 |", REPRODUCIBILITY,
     _path_run("default", "erosion_front_x layer_ahead 0"), ".5f", 1),
    ("docs/performance.md", "1,728 / 26,525 unknowns | 3.1 / {} |", REPRODUCIBILITY,
     _path_run("default", "refactorise_ms 26525 unknowns"), ".0f", 1),
    ("docs/performance.md", "| 3.1 / 170 | 7.8 / {} |", REPRODUCIBILITY,
     _path_run("COMPATIBLE", "refactorise_ms 26525 unknowns"), ".0f", 1),
    ("docs/performance.md", "cost 1 to 2 % on the default trapezoids, {} % on the cylinder",
     MKL_MODES, _compatible_extra("cylinder-rigid"), ".0f", 100),
    ("docs/performance.md", "% on the cylinder and {} % on the 20,000-triangle mesh",
     MKL_MODES, _compatible_extra("mesh-20k"), ".0f", 100),
    ("CHANGELOG.md", "whose SSE2 kernels cost {} % more processor time", MKL_MODES,
     _compatible_extra("mesh-20k"), ".0f", 100),
    # --- three dimensions (benchmarks/three_d_collapse.py, collapse_runs.py --compare)
    # --- the 3D walls held strongly (collapse_runs.py --compare, strong_walls.py)
    ("docs/three_d.md", "the two runs take the same {} steps", WALLS_PAIR,
     "rectangle-rigid.3d-strong.steps", "d", 1),
    ("docs/three_d.md", "side wall stay within {} m of each other", WALLS,
     lambda d: max(d[f"front_x_{w}_max_difference_by_time"]["0.100"]
                   for w in ("centre", "side")), ".1e", 1),
    ("docs/three_d.md", "free surfaces within {} m on average", WALLS,
     lambda d: d["free_surface"]["0.100"]["mean_m"], ".1e", 1),
    ("docs/three_d.md", "differs by up to {} mm for that step", WALLS,
     lambda d: d["front_x_side_max_difference_by_time"]["0.200"], ".1f", 1e3),
    ("docs/three_d.md", "the runout differs by {} %", WALLS_PAIR,
     "rectangle-rigid.relative_changes.runout_m", ".2f", 100),
    ("docs/three_d.md", "by at most {} mm along the centre line", WALLS,
     lambda d: d["free_surface"]["0.200"]["max_m"], ".2f", 1e3),
    ("docs/three_d.md", "along the centre line and {} mm at the wall", WALLS,
     lambda d: d["free_surface_wall"]["0.200"]["max_m"], ".2f", 1e3),
    ("docs/three_d.md", "and the free surfaces {} m apart", WALLS_2D,
     lambda d: max(g["max_m"] for r in d.values() for g in r["free_surfaces"].values()),
     ".1f", 1),
    ("docs/three_d.md", "the deposits' fronts differ by {} mm along the centre line",
     WALLS_REST, lambda d: d["last_rows"]["strong"]["front_x_centre"]
     - d["last_rows"]["penalty"]["front_x_centre"], "+.1f", 1e3),
    ("docs/three_d.md", "centre line and {} mm at the side wall", WALLS_REST,
     lambda d: d["last_rows"]["strong"]["front_x_side"]
     - d["last_rows"]["penalty"]["front_x_side"], "+.1f", 1e3),
    ("docs/three_d.md", "surfaces are within {} mm, the wall ones", WALLS_REST,
     lambda d: d["free_surface"]["0.400"]["max_m"], ".2f", 1e3),
    ("docs/three_d.md", "the wall ones within {} mm (where", WALLS_REST,
     lambda d: d["free_surface_wall"]["0.400"]["max_m"], ".0f", 1e3),
    ("docs/three_d.md", "(up to {} mm/s in a small share", WALLS_REST,
     lambda d: d["last_rows"]["strong"]["max_speed"], ".1f", 1e3),
    ("docs/three_d.md", "the run stops at {} s against", WALLS_REST_PAIR,
     "rectangle-rigid.3d-rest-strong.stop_time_s", ".3f", 1),
    ("docs/three_d.md", "s against {} s with the penalty", WALLS_REST_PAIR,
     "rectangle-rigid.3d-rest-penalty.stop_time_s", ".3f", 1),
    # --- the 3D iterative solve (benchmarks/three_d_krylov.py)
    ("docs/three_d.md", "(strong walls, dt = {} s)", KRYLOV_FRONT_20,
     "[eps=1e-06&schur=cahouet-chabard].dt", ".0e", 1),
    ("docs/three_d.md", "needs {} steps (123 with BDDC)", KRYLOV_EXACT_20,
     "[eps=1e-06].gmres_steps", "d", 1),
    ("docs/three_d.md", "79, 101, 123, {} steps for 973", KRYLOV_FLOWING_14,
     "[eps=1e-06].gmres_steps", "d", 1),
    ("docs/three_d.md", "at 5,414 unknowns: 258-{} steps", KRYLOV_FRONT_20,
     "max:[schur=cahouet-chabard].gmres_steps", "d", 1),
    ("docs/three_d.md", "does not reach 1e-8 within {} steps", KRYLOV_REST_04,
     "max:[schur=cahouet-chabard].gmres_steps", "d", 1),
    ("docs/three_d.md", "in residual ({} steps) leaves the velocity", KRYLOV_PLUG,
     "[eps=1e-06&schur=cahouet-chabard].gmres_steps", "d", 1),
    # --- the cost growth (benchmarks/three_d_fieldsplit_cost.py)
    ("docs/three_d.md", "every solve converged, within {} of UMFPACK's solution", COST,
     _cost(FIELDSPLIT_SOLVERS, "relative_difference", max), ".1e", 1),
    ("docs/three_d.md", "The direct solves grow as N^{} to N^1.7", COST,
     _cost(DIRECT_SOLVERS, "exponent"), ".1f", 1),
    ("docs/three_d.md", "grow as N^1.5 to N^{} in these sizes", COST,
     _cost(DIRECT_SOLVERS, "exponent", max), ".1f", 1),
    ("docs/three_d.md", "between the two largest sizes, up to {}, is rising", COST,
     _cost(DIRECT_SOLVERS, "exponent_last_two", max), ".1f", 1),
    ("docs/three_d.md", "the fieldsplit solves as N^{} to N^1.6", COST,
     _cost(FIELDSPLIT_SOLVERS, "exponent"), ".2f", 1),
    ("docs/three_d.md", "as N^1.25 to N^{}, more than", COST,
     _cost(FIELDSPLIT_SOLVERS, "exponent", max), ".1f", 1),
    ("docs/three_d.md", "grow little with LSC ({} to 34 at rest)", COST,
     lambda d: d["states"]["rest"]["solvers"]["lsc-gamg-flexible"]["steps"][0], "d", 1),
    ("docs/three_d.md", "grow little with LSC (26 to {} at rest)", COST,
     lambda d: d["states"]["rest"]["solvers"]["lsc-gamg-flexible"]["steps"][-1], "d", 1),
    ("docs/three_d.md", "at rest and on the front (15 to {}, 11 to 43)", COST,
     lambda d: d["states"]["rest"]["solvers"]["selfp-gamg-flexible"]["steps"][-1], "d", 1),
    ("docs/three_d.md", "at rest and on the front (15 to 59, 11 to {})", COST,
     lambda d: d["states"]["front"]["solvers"]["selfp-gamg-flexible"]["steps"][-1], "d", 1),
    ("docs/three_d.md", "state, {} to 0.72 times `selfp`'s at 18,192", COST,
     _lsc_over("selfp-gamg-flexible", min), ".2f", 1),
    ("docs/three_d.md", "state, 0.28 to {} times `selfp`'s at 18,192", COST,
     _lsc_over("selfp-gamg-flexible", max), ".2f", 1),
    ("docs/three_d.md", "and still {} to 5.8 times UMFPACK's at 37,274", COST,
     lambda d: min(e["solvers"]["lsc-gamg-flexible"]["cpu_s"][-1]
                   / e["solvers"]["umfpack"]["cpu_s"][-1] for e in d["states"].values()),
     ".1f", 1),
    ("docs/three_d.md", "and still 3.9 to {} times UMFPACK's at 37,274", COST,
     lambda d: max(e["solvers"]["lsc-gamg-flexible"]["cpu_s"][-1]
                   / e["solvers"]["umfpack"]["cpu_s"][-1] for e in d["states"].values()),
     ".1f", 1),
    ("docs/three_d.md", "grows as N^{} to N^1.7 here (N^4/3", COST,
     _cost(DIRECT_SOLVERS, "memory_exponent"), ".1f", 1),
    ("docs/three_d.md", "grows as N^1.4 to N^{} here (N^4/3", COST,
     _cost(DIRECT_SOLVERS, "memory_exponent", max), ".1f", 1),
    ("docs/three_d.md", "peaked at {} to 1.2 GB at 37,274", COST,
     lambda d: min(e["peak_rss_mb"][-1] for e in d["states"].values()), ".1f", 1 / 1024),
    ("docs/three_d.md", "peaked at 1.1 to {} GB at 37,274", COST,
     lambda d: max(e["peak_rss_mb"][-1] for e in d["states"].values()), ".1f", 1 / 1024),
    ("docs/three_d.md", "LSC becomes as cheap as UMFPACK at {} to 9e6", COST,
     _cross("lsc-gamg-flexible", 1, min), ".1e", 1),
    ("docs/three_d.md", "as cheap as UMFPACK at 1.5e6 to {} unknowns", COST,
     _cross("lsc-gamg-flexible", 1, max), ".0e", 1),
    ("docs/three_d.md", "`selfp` at {} flowing", COST,
     lambda d: d["states"]["flowing"]["crossover"]["selfp-gamg-flexible"]["1"], ".1e", 1),
    ("docs/three_d.md", "a parallel efficiency of {}, and only", COST, "efficiency", "g", 1),
    ("docs/three_d.md", "every rank holds at least {} unknowns", COST, "per_rank", ",d", 1),
    ("docs/three_d.md", "measured about {} % parallel efficiency", COST,
     lambda d: d["cited_efficiency"]["value"], ".0f", 100),
    ("docs/three_d.md", "on 3D elasticity up to {} processors", COST,
     lambda d: d["cited_efficiency"]["processors"], "d", 1),
    ("docs/three_d.md", "the same one-process run to {} s", COST_LSC, "t_end", "g", 1),
    ("docs/three_d.md", "average over a minute {} to 6.1 at the end of each state", COST,
     lambda d: min(_check_record(s)["load_average"][0] for s in STATES), ".1f", 1),
    ("docs/three_d.md", "average over a minute 5.7 to {} at the end of each state", COST,
     lambda d: max(_check_record(s)["load_average"][0] for s in STATES), ".1f", 1),
    ("docs/three_d.md", "At {} unknowns UMFPACK took", COST,
     lambda d: d["checks"][0]["unknowns"], ",d", 1),
    ("docs/three_d.md", "UMFPACK took {} to 1.54 times its fit's time", COST,
     _check("umfpack", min), ".2f", 1),
    ("docs/three_d.md", "UMFPACK took 1.12 to {} times its fit's time", COST,
     _check("umfpack", max), ".2f", 1),
    ("docs/three_d.md", "and LSC {} to 1.11 times its own", COST,
     _check("lsc-gamg-flexible", min), ".2f", 1),
    ("docs/three_d.md", "and LSC 0.83 to {} times its own", COST,
     _check("lsc-gamg-flexible", max), ".2f", 1),
    ("docs/three_d.md", "iterations and {} GMRes steps, its fronts within 1.0e-12", COST_LSC_2,
     "krylov_iterations", "d", 1),
    ("docs/three_d.md", "its fronts within {} m of `masterinverse`'s at the centre, in 0.63",
     COST_LSC_2, lambda d: abs(d["runout_centre_m"] - _scaled_collapse("n2_t0.03")[
         "runout_centre_m"]), ".1e", 1),
    ("docs/three_d.md", "in {} times `selfp`'s processor time on two", COST_LSC_2,
     _lsc_collapse_over("n2_fieldsplit_t0.03"), ".2f", 1),
    ("docs/three_d.md", "ranks and {} times `masterinverse`'s (MPICH", COST_LSC_2,
     _lsc_collapse_over("n2_t0.03"), ".1f", 1),
    ("docs/three_d.md", "(LSC {} to 1.38, predicted 1.0 to 1.3", COST,
     _cost(("lsc-gamg-flexible",), "exponent"), ".2f", 1),
    ("docs/three_d.md", "(LSC 1.25 to {}, predicted 1.0 to 1.3", COST,
     _cost(("lsc-gamg-flexible",), "exponent", max), ".2f", 1),
    ("docs/three_d.md", "`selfp` {} to 1.61, predicted 1.1 to 1.4", COST,
     _cost(("selfp-gamg-flexible",), "exponent"), ".2f", 1),
    ("docs/three_d.md", "`selfp` 1.30 to {}, predicted 1.1 to 1.4", COST,
     _cost(("selfp-gamg-flexible",), "exponent", max), ".2f", 1),
    ("docs/three_d.md", "within {} of `masterinverse`'s solution.", COST,
     lambda d: max(json.loads((RESULTS / "three_d_fieldsplit" / (
         f"fieldsplit_ranks_lsc-gamg-flexible_rigid_scaled_{s}_h{h}_n2.json")).read_text(
         ))["relative_difference"] for s in STATES for h in ("0.04", "0.02")), ".1e", 1),
    ("docs/three_d.md", "It takes the direct run's {} steps and 111", COST_LSC, "steps", "d", 1),
    ("docs/three_d.md", "38 steps and {} nonlinear iterations, its fronts within 9.9e-13",
     COST_LSC, "nonlinear_iterations", "d", 1),
    ("docs/three_d.md", "on 16 and 64 ranks at {} and 6.4e5 unknowns", COST,
     _cross("lsc-gamg-flexible", 16, max), ".1e", 1),
    ("docs/three_d.md", "on 16 and 64 ranks at 1.6e5 and {} unknowns", COST,
     _cross("lsc-gamg-flexible", 64, max), ".1e", 1),
    ("docs/three_d.md", "on every state from about {} unknowns on 16 ranks", COST,
     _cross("lsc-gamg-flexible", 16, max), ".1e", 1),
    ("docs/three_d.md", "the fits give UMFPACK about {} s per solve at rest", COST,
     lambda d: d["states"]["rest"]["solvers"]["umfpack"]["at_1e6_s"], ".0f", 1),
    ("docs/three_d.md", "a factor of about {} GB on one node", COST,
     lambda d: d["states"]["rest"]["solvers"]["umfpack"]["memory_at_1e6_mb"], ".0f", 1 / 1024),
    ("docs/three_d.md", "on one node ({} to 113 GB by", COST,
     _cost(DIRECT_SOLVERS, "memory_at_1e6_mb"), ".0f", 1 / 1024),
    ("docs/three_d.md", "on one node (46 to {} GB by", COST,
     _cost(DIRECT_SOLVERS, "memory_at_1e6_mb", max), ".0f", 1 / 1024),
    ("docs/three_d.md", "against LSC's {} s on one process", COST,
     lambda d: d["states"]["rest"]["solvers"]["lsc-gamg-flexible"]["at_1e6_s"], ".0f", 1),
    ("docs/three_d.md", "about {} s on 100 ranks", COST,
     lambda d: d["states"]["rest"]["solvers"]["lsc-gamg-flexible"]["at_1e6_s"]
     / (100 * d["efficiency"]), ".0f", 1),
    ("docs/three_d.md", "The fits are extrapolated {} times past", COST,
     lambda d: 1e6 / d["states"]["rest"]["unknowns"][-1], ".0f", 1),
    ("docs/three_d.md", "{} m of the direct run's at the centre and 1.9e-12", COST_LSC,
     _scaled_apart("runout_centre_m", "n1_t0.03"), ".1e", 1),
    ("docs/three_d.md", "at the centre and {} m at the wall; it takes", COST_LSC,
     _scaled_apart("runout_wall_m", "n1_t0.03"), ".1e", 1),
    ("docs/three_d.md", "it takes {} times `selfp`'s GMRes steps", COST_LSC,
     lambda d: d["krylov_iterations"] / _scaled_collapse("n1_fieldsplit_t0.03")[
         "krylov_iterations"], ".1f", 1),
    ("docs/three_d.md", "(at most {} in one solve) but", COST_LSC, "krylov_largest", "d", 1),
    ("docs/three_d.md", "but {} times its processor time", COST_LSC,
     _lsc_collapse_over("n1_fieldsplit_t0.03"), ".2f", 1),
    ("docs/three_d.md", "its processor time, {} times the direct run's", COST_LSC,
     _lsc_collapse_over("n1_t0.03"), ".1f", 1),
    ("docs/three_d.md", "({} s of it in the fieldsplit solves, cProfile's", COST_LSC,
     lambda d: next(p["own_s"] for p in d["profile"] if "fieldsplit" in p["function"]),
     ".0f", 1),
    # --- the scaled fieldsplit solve (benchmarks/three_d_fieldsplit.py --scaled)
    ("docs/three_d.md", "it takes the same {} steps, 190\niterations and 2148", SCALED_N2_01,
     "steps", "d", 1),
    ("docs/three_d.md", "the same 108 steps, {}\niterations and 2148", SCALED_N2_01,
     "nonlinear_iterations", "d", 1),
    ("docs/three_d.md", "iterations and {} GMRes steps, its fronts within 6.1e-11", SCALED_N2_01,
     "krylov_iterations", "d", 1),
    ("docs/three_d.md", "its fronts within {} m of the one-process direct", SCALED_N2_01,
     lambda d: max(_scaled_apart(k, "n1_t0.1")(d) for k in ("runout_centre_m",
                                                             "runout_wall_m")), ".1e", 1),
    ("docs/three_d.md", "in {} processor seconds (2.4 times", SCALED_N2_01, "cpu_s", ".0f", 1),
    ("docs/three_d.md", "seconds ({} times the one-process fieldsplit", SCALED_N2_01,
     _scaled_ratio("n1_fieldsplit_t0.1"), ".1f", 1),
    ("docs/three_d.md", "within {} of `masterinverse`'s solution", SCALED_TABLE,
     lambda d: max(json.loads((RESULTS / "three_d_fieldsplit" / (
         f"fieldsplit_ranks_flexible_rigid_scaled_{s}_h{h}_n2.json")).read_text(
         ))["relative_difference"] for s in STATES for h in ("0.04", "0.02")), ".1e", 1),
    ("docs/three_d.md", "the set-up apart ({} to 0.8 s)", SCALED_TABLE,
     lambda d: min(_timing(k, s)["convert_setup"] for k in TIMING_NAMES for s in STATES),
     ".1f", 1),
    ("docs/three_d.md", "the set-up apart (0.4 to {} s)", SCALED_TABLE,
     lambda d: max(_timing(k, s)["convert_setup"] for k in TIMING_NAMES for s in STATES),
     ".1f", 1),
    ("docs/three_d.md", "its solves take {} to 0.60 times `selfp`'s", SCALED_TABLE,
     lambda d: min(_lsc_over_selfp(d)), ".2f", 1),
    ("docs/three_d.md", "its solves take 0.35 to {} times `selfp`'s", SCALED_TABLE,
     lambda d: max(_lsc_over_selfp(d)), ".2f", 1),
    ("docs/three_d.md", "All are {} to 16.6 times the direct solve", SCALED_TABLE,
     lambda d: min(_over_direct(d)), ".1f", 1),
    ("docs/three_d.md", "All are 5.4 to {} times the direct solve", SCALED_TABLE,
     lambda d: max(_over_direct(d)), ".1f", 1),
    ("docs/three_d.md", "the scaled solve takes the direct run's {} steps and 111", SCALED_N1,
     "steps", "d", 1),
    ("docs/three_d.md", "Run on to t_end = {} s (`--stop-at 0.1`", SCALED_N1_01, "t_end", "g", 1),
    ("docs/three_d.md", "again takes the direct run's {} steps and 190", SCALED_N1_01, "steps",
     "d", 1),
    ("docs/three_d.md", "{} nonlinear\niterations, its fronts within 6.3e-12", SCALED_N1_01,
     "nonlinear_iterations", "d", 1),
    ("docs/three_d.md", "its fronts within {} m at the centre and 3.1e-11", SCALED_N1_01,
     _scaled_apart("runout_centre_m", "n1_t0.1"), ".1e", 1),
    ("docs/three_d.md", "at the centre and {} m at the wall, with 2148", SCALED_N1_01,
     _scaled_apart("runout_wall_m", "n1_t0.1"), ".1e", 1),
    ("docs/three_d.md", "with {}\nGMRes steps over its 190 solves", SCALED_N1_01,
     "krylov_iterations", "d", 1),
    ("docs/three_d.md", "GMRes steps over its {} solves (at most 15", SCALED_N1_01,
     "krylov_solves", "d", 1),
    ("docs/three_d.md", "its processor time is {} times\nthe direct run's", SCALED_N1_01,
     _scaled_ratio("n1_t0.1"), ".1f", 1),
    ("docs/three_d.md", "the direct run's: {} s in the fieldsplit solves", SCALED_N1_01,
     lambda d: next(p["own_s"] for p in d["profile"] if "fieldsplit" in p["function"]),
     ".0f", 1),
    ("docs/three_d.md", "against {} s to 0.03 s", SCALED_N1,
     lambda d: next(p["own_s"] for p in d["profile"] if "fieldsplit" in p["function"]),
     ".0f", 1),
    ("docs/three_d.md", "for {} times the\nouter GMRes steps", SCALED_N1_01,
     lambda d: d["krylov_iterations"] / _scaled_collapse("n1_fieldsplit_t0.03")[
         "krylov_iterations"], ".1f", 1),
    ("docs/three_d.md", "its PARDISO calls {} s)", "three_d_fieldsplit/rest_h0.04_n1_t0.1.json",
     lambda d: next(p["own_s"] for p in d["profile"] if "pardiso" in p["function"]), ".2f", 1),
    ("docs/three_d.md", "its fronts within {} m of the direct run's at the centre",
     SCALED_N1, _scaled_apart("runout_centre_m", "n1_t0.03"), ".1e", 1),
    ("docs/three_d.md", "at the centre and {} m\nat the wall, with", SCALED_N1,
     _scaled_apart("runout_wall_m", "n1_t0.03"), ".1e", 1),
    ("docs/three_d.md", "with {} GMRes steps over its 111 solves", SCALED_N1,
     "krylov_iterations", "d", 1),
    ("docs/three_d.md", "GMRes steps over its {} solves", SCALED_N1, "krylov_solves", "d", 1),
    ("docs/three_d.md", "(at most {} in one)", SCALED_N1, "krylov_largest", "d", 1),
    ("docs/three_d.md", "in one): {} times the\ndirect solve's processor time", SCALED_N1,
     _scaled_ratio("n1_t0.03"), ".1f", 1),
    ("docs/three_d.md", "its fronts within {} m\nof `masterinverse`'s at the centre", SCALED_N2,
     _scaled_apart("runout_centre_m", "n2_t0.03"), ".1e", 1),
    ("docs/three_d.md", "its processor time is {} times the one-process", SCALED_N2,
     _scaled_ratio("n1_fieldsplit_t0.03"), ".1f", 1),
    ("docs/three_d.md", "run's and {} times `masterinverse`'s", SCALED_N2,
     _scaled_ratio("n2_t0.03"), ".1f", 1),
    ("docs/three_d.md", "the predicted 5 to 15 times,\n{} GMRes steps a solve", SCALED_N1,
     lambda d: d["krylov_iterations"] / d["krylov_solves"], ".1f", 1),
    ("docs/three_d.md", "unscaled, the setting's variant stopped {} from the direct solve",
     SCALED.format("flexible_rigid", "rest", "0.02"), "relative_difference", ".1e", 1),
    ("docs/three_d.md", "at rest and {} flowing at 5,414 unknowns, and needed",
     SCALED.format("flexible_rigid", "flowing", "0.02"), "relative_difference", ".1e", 1),
    ("docs/three_d.md", "and needed {} steps at rest; scaled",
     SCALED.format("flexible_rigid", "rest", "0.02"), "steps", "d", 1),
    ("docs/three_d.md", "scaled, it takes {} / 12 / 18",
     SCALED.format("flexible_rigid_scaled", "rest", "0.02"), "steps", "d", 1),
    ("docs/three_d.md", "scaled, it takes 27 / {} / 18",
     SCALED.format("flexible_rigid_scaled", "flowing", "0.02"), "steps", "d", 1),
    ("docs/three_d.md", "scaled, it takes 27 / 12 / {}",
     SCALED.format("flexible_rigid_scaled", "front", "0.02"), "steps", "d", 1),
    ("docs/three_d.md", "and Cahouet-Chabard stops up to {} from the direct solve",
     SCALED_TABLE, lambda d: d["within_1e-6"]["Cahouet-Chabard, unscaled"]["largest_distance"],
     ".0e", 1),
    ("docs/three_d.md", "(38 and {} at\n  18,192 unknowns)",
     SCALED.format("cahouet-chabard_rigid_scaled", "front", "0.014"), "steps", "d", 1),
    ("docs/three_d.md", "({} and 58 at", SCALED.format("cahouet-chabard_rigid_scaled",
                                                    "flowing", "0.014"), "steps", "d", 1),
    ("docs/three_d.md", "(at rest {} to 31, on the front",
     SCALED.format("lsc-gamg-flexible_rigid_scaled", "rest", "0.04"), "steps", "d", 1),
    ("docs/three_d.md", "(at rest 26 to {}, on the front",
     SCALED.format("lsc-gamg-flexible_rigid_scaled", "rest", "0.014"), "steps", "d", 1),
    ("docs/three_d.md", "on the front {} to 26), the",
     SCALED.format("lsc-gamg-flexible_rigid_scaled", "front", "0.04"), "steps", "d", 1),
    ("docs/three_d.md", "on the front 23 to {}), the",
     SCALED.format("lsc-gamg-flexible_rigid_scaled", "front", "0.014"), "steps", "d", 1),
    ("docs/three_d.md", "more than `selfp`'s flowing ({})",
     SCALED.format("lsc-gamg-flexible_rigid_scaled", "flowing", "0.014"), "steps", "d", 1),
    ("docs/three_d.md", "leaves the flowing column up to {} from\nit with `selfp`", SCALED_TABLE,
     lambda d: d["within_1e-6"]["selfp, scaled"]["largest_distance_at_1e-8"], ".1e", 1),
    ("docs/three_d.md", "but takes up to {} steps (predicted at most 50)",
     SCALED.format("cahouet-chabard_rigid_scaled", "front", "0.014"), "steps", "d", 1),
    ("docs/three_d.md", "its steps grow by up to {} % from 973", SCALED.format(
        "cahouet-chabard_rigid_scaled", "front", "0.014"), lambda d: d["steps"] / json.loads(
        (RESULTS / SCALED.format("cahouet-chabard_rigid_scaled", "front", "0.04")).read_text(
        ))["steps"] - 1, ".0f", 100),
    ("docs/three_d.md", "at 973 and 5,414 unknowns and {} more at 18,192",
     SCALED.format("flexible_rigid_scaled", "rest", "0.014"), lambda d: d["steps"] - json.loads(
        (RESULTS / SCALED.format("cahouet-chabard_rigid_scaled", "rest", "0.014")).read_text(
        ))["steps"], "d", 1),
    ("docs/three_d.md", "of the direct solve in {} of its 6 solves", SCALED_TABLE,
     lambda d: d["within_1e-6"]["selfp, unscaled"]["reached"], "d", 1),
    ("docs/three_d.md", "of the direct solve in 2 of its {} solves", SCALED_TABLE,
     lambda d: d["within_1e-6"]["selfp, unscaled"]["records"], "d", 1),
    ("docs/three_d.md", "scaled system between {} and 3.5e-7 on", SCALED_TABLE,
     _within("selfp, scaled", "own_residual", 0), ".1e", 1),
    ("docs/three_d.md", "scaled system between 4.3e-10 and {} on", SCALED_TABLE,
     _within("selfp, scaled", "own_residual", 1), ".1e", 1),
    ("docs/three_d.md", "true relative residual is anywhere between {} and", SCALED_TABLE,
     _within("selfp, scaled", "true_residual", 0), ".1e", 1),
    ("docs/three_d.md", "anywhere between 1.4e-11 and\n  {}: the unscaled", SCALED_TABLE,
     _within("selfp, scaled", "true_residual", 1), ".1e", 1),
    ("docs/three_d.md", "leaves both fields within {}.", SCALED_TABLE,
     lambda d: d["within_1e-6"]["selfp, scaled"]["largest_distance"], ".1e", 1),
    # --- PETSc's fieldsplit (benchmarks/three_d_fieldsplit.py)
    ("docs/three_d.md", "its fronts within\n{} m of `masterinverse`'s", SPLIT_COLLAPSE_2,
     lambda d: _fronts_apart("runout_centre_m", 2)(d), ".1e", 1),
    ("docs/three_d.md", "the two ranks spend {} times the one-process", SPLIT_COLLAPSE_2,
     lambda d: d["cpu_s"] / _collapse("n1_fieldsplit_t0.03")["cpu_s"], ".1f", 1),
    ("docs/three_d.md", "at 20 to {} times its processor time", SPLIT_COLLAPSE_2,
     lambda d: d["cpu_s"] / _collapse("n2_t0.03")["cpu_s"], ".0f", 1),
    ("docs/three_d.md", "takes {} / 8 / 57 steps at rest", RIGID_2.format("rest"),
     "steps", "d", 1),
    ("docs/three_d.md", "takes 125 / {} / 57 steps at rest", RIGID_2.format("flowing"),
     "steps", "d", 1),
    ("docs/three_d.md", "takes 125 / 8 / {} steps at rest", RIGID_2.format("front"),
     "steps", "d", 1),
    ("docs/three_d.md", "so every run stops at t_end = {} s",
     "three_d_collapse/rest_h0.04_n1_fieldsplit_t0.03.json", "t_end", "g", 1),
    ("docs/three_d.md", "(no remesh yet, the front {} mm out)",
     "three_d_collapse/rest_h0.04_n1_t0.03.json", lambda d: d["runout_centre_m"] - 0.2,
     ".1f", 1e3),
    ("docs/three_d.md", "its\nfronts agree to {} m at the centre", SPLIT_COLLAPSE,
     lambda d: _fronts_apart("runout_centre_m", 1)(d), ".1e", 1),
    ("docs/three_d.md", "at the centre and {} m at the wall; it costs", SPLIT_COLLAPSE,
     lambda d: _fronts_apart("runout_wall_m", 1)(d), ".1e", 1),
    ("docs/three_d.md", "it costs {} times the\nprocessor time", SPLIT_COLLAPSE,
     lambda d: d["cpu_s"] / _collapse("n1_t0.03")["cpu_s"], ".1f", 1),
    ("docs/three_d.md", "processor time, {} s of it in the fieldsplit solves", SPLIT_COLLAPSE,
     lambda d: next(p["own_s"] for p in d["profile"] if "fieldsplit" in p["function"]),
     ".0f", 1),
    ("docs/three_d.md", "make the unscaled FGMRes converge at rest there, in {} steps",
     RIGID.format("flexible_rigid", "rest"), "steps", "d", 1),
    ("docs/three_d.md", "variant is {} from the direct solve at rest",
     RIGID.format("flexible_rigid", "rest"), "relative_difference", ".1e", 1),
    ("docs/three_d.md", "at rest and {} flowing at 5,414",
     RIGID.format("flexible_rigid", "flowing"), "relative_difference", ".1e", 1),
    ("docs/three_d.md", "cut the left-preconditioned variant's steps by {} % at rest",
     RIGID.format("rigid", "rest"),
     lambda d: 1 - d["steps"] / _left_steps("rest"), ".0f", 100),
    ("docs/three_d.md", "at rest and {} % flowing", RIGID.format("rigid", "flowing"),
     lambda d: 1 - d["steps"] / _left_steps("flowing"), ".0f", 100),
    ("docs/three_d.md", "flowing and {} % on the front at 5,414", RIGID.format("rigid", "front"),
     lambda d: 1 - d["steps"] / _left_steps("front"), ".0f", 100),
    ("docs/three_d.md", "selfp with GAMG, takes {} steps at rest", SPLIT_REST_14,
     "[variant=selfp-gamg].steps", "d", 1),
    ("docs/three_d.md", "and {} at 37,274 (about", SPLIT_REST_10,
     "[variant=selfp-gamg].steps", "d", 1),
    ("docs/three_d.md", "and {} processor seconds against UMFPACK's", SPLIT_REST_14,
     lambda d: _split_cpu(d, "selfp-gamg"), ".2f", 1),
    ("docs/three_d.md", "UMFPACK's {} at 18,192", SPLIT_REST_14,
     "[variant=selfp-gamg].cpu_s.direct", ".2f", 1),
    ("docs/three_d.md", "18,192, {} against", SPLIT_REST_10,
     lambda d: _split_cpu(d, "selfp-gamg"), ".2f", 1),
    ("docs/three_d.md", "against {} at 37,274: on one", SPLIT_REST_10,
     "[variant=selfp-gamg].cpu_s.direct", ".2f", 1),
    ("docs/three_d.md", "sequential and slow (about {} s at 18,192", SPLIT_REST_14,
     lambda d: _split_cpu(d, "lsc-lu"), ".0f", 1),
    ("docs/three_d.md", "on one process: {} / 37 / 43 at rest", RANKS.format("rest", "0.02", 2),
     "steps", "d", 1),
    ("docs/three_d.md", "30 / {} / 43 at rest", RANKS.format("rest", "0.014", 2),
     "steps", "d", 1),
    ("docs/three_d.md", "30 / 37 / {} at rest", RANKS.format("rest", "0.01", 2),
     "steps", "d", 1),
    ("docs/three_d.md", "(one process: {} / 38 / 44)", RANKS.format("rest", "0.02", 1),
     "steps", "d", 1),
    ("docs/three_d.md", "(one process: 30 / {} / 44)", RANKS.format("rest", "0.014", 1),
     "steps", "d", 1),
    ("docs/three_d.md", "(one process: 30 / 38 / {})", RANKS.format("rest", "0.01", 1),
     "steps", "d", 1),
    ("docs/three_d.md", "{} flowing and 43 on the front", RANKS.format("flowing", "0.014", 2),
     "steps", "d", 1),
    ("docs/three_d.md", "31 flowing and {} on the front", RANKS.format("front", "0.014", 2),
     "steps", "d", 1),
    ("docs/three_d.md", "within {} of the direct solve (`masterinverse`)",
     RANKS.format("rest", "0.01", 2), "relative_difference", ".1e", 1),
    ("docs/three_d.md", "velocity's L2 norm is one process's to {}",
     RANKS.format("rest", "0.014", 2), _ranks_apart("velocity_l2"), ".1e", 1),
    ("docs/three_d.md", "the work: {} and 1,170 million", RANKS.format("rest", "0.014", 2),
     lambda d: d["petsc_flops_per_rank"][0], ",d", 1e-6),
    ("docs/three_d.md", "1,266 and {} million", RANKS.format("rest", "0.014", 2),
     lambda d: d["petsc_flops_per_rank"][1], ",d", 1e-6),
    ("docs/three_d.md", "against {} on one process at rest", RANKS.format("rest", "0.014", 1),
     lambda d: d["petsc_flops_per_rank"][0], ",d", 1e-6),
    ("docs/three_d.md", "spends up to {} processor seconds", RANKS.format("rest", "0.014", 2),
     lambda d: max(c["setup"] + c["solve"] for c in d["cpu_s_per_rank"]), ".2f", 1),
    ("docs/three_d.md", "there against {} on one process", RANKS.format("rest", "0.014", 1),
     lambda d: d["cpu_s_per_rank"][0]["setup"] + d["cpu_s_per_rank"][0]["solve"], ".2f", 1),
    ("docs/three_d.md", "The runouts differ by {} %", PLANE_14, "runout_relative", "+.2f",
     100),
    ("docs/three_d.md", "and {} mm apart behind the front's last mesh.size", PLANE_14,
     _at("surface_distance_behind_front_max_m", "0.2"), ".2f", 1e3),
    ("docs/three_d.md", "they are up to {} mm apart", PLANE_14,
     _at("surface_distance_max_m", "0.2"), ".1f", 1e3),
    ("docs/three_d.md", "({} m in 3D", PLANE_14, "runout_3d_m", ".4f", 1),
    ("docs/three_d.md", "in 3D against {} m)", PLANE_14, "runout_2d_m", ".4f", 1),
    ("docs/three_d.md", "surfaces are {} mm apart on average", PLANE_14,
     _at("surface_distance_mean_m", "0.1"), ".2f", 1e3),
    ("docs/three_d.md", "and {} mm at the second", PLANE_14,
     _at("surface_distance_mean_m", "0.2"), ".2f", 1e3),
    ("docs/three_d.md", "and at most {} mm", PLANE_14,
     _at("surface_distance_behind_front_max_m", "0.1"), ".2f", 1e3),
    ("docs/three_d.md", "surfaces at most {} mm and", PLANE_20,
     _at("surface_distance_behind_front_max_m", "0.1"), ".2f", 1e3),
    ("docs/three_d.md", "times, {} mm at the foot", PLANE_20,
     _at("surface_distance_max_m", "0.2"), ".1f", 1e3),
    # mu(I) and the trapezoid against plane strain at two sizes (three_d_collapse.py plane-strain)
    ("docs/three_d.md", "3D runout is {} % short\n  of the plane-strain", PLANE_MU_20,
     lambda d: -d["runout_relative"], ".2f", 100),
    ("docs/three_d.md", "coarser size and {} % at the finer", PLANE_MU_14,
     lambda d: -d["runout_relative"], ".2f", 100),
    ("docs/three_d.md", "centre-line surfaces are {} mm apart behind the foot", PLANE_TRAP_30,
     _at("surface_distance_behind_front_max_m", "0.1"), ".2f", 1e3),
    ("docs/three_d.md", "coarser size and {} mm at the finer", PLANE_TRAP_20,
     _at("surface_distance_behind_front_max_m", "0.1"), ".2f", 1e3),
    ("docs/three_d.md", "(observed orders {} and", PLANE_MU_14,
     lambda d: _order(PLANE_MU_20, d, "runout_relative"), ".1f", 1),
    ("docs/three_d.md", "(observed orders 2.0 and {})", PLANE_TRAP_20,
     lambda d: _order(PLANE_TRAP_30, d, "surface_distance"), ".1f",
     1),
    # the cost table (benchmarks/three_d_collapse.py rest [--ranks 2])
    ("docs/three_d.md", "| 1 | {} s | 0.3971 m", REST_1, "stop_time_s", ".3f", 1),
    ("docs/three_d.md", "| 1 | 0.571 s | {} m, 0.3461 m", REST_1, "runout_centre_m", ".4f", 1),
    ("docs/three_d.md", "| 0.3971 m, {} m | 669", REST_1, "runout_wall_m", ".4f", 1),
    ("docs/three_d.md", "m | {} | 2,123 | 13 |", REST_1, "steps", ",d", 1),
    ("docs/three_d.md", "| 669 | {} | 13 | 116 s", REST_1, "nonlinear_iterations", ",d", 1),
    ("docs/three_d.md", "| 2,123 | {} | 116 s", REST_1, "remeshes", "d", 1),
    ("docs/three_d.md", "| 13 | {} s | 861 s", REST_1, "cpu_s", ".0f", 1),
    ("docs/three_d.md", "| 116 s | {} s | 9.7", REST_1, "wall_s", ".0f", 1),
    ("docs/three_d.md", "| 861 s | {}, 11.4 |", REST_1, lambda d: d["load_average"][0], ".1f", 1),
    ("docs/three_d.md", "| 9.7, {} | 582 MB", REST_1, lambda d: d["load_average"][3], ".1f", 1),
    ("docs/three_d.md", ", 11.4 | {} MB |", REST_1, "peak_mb", ".0f", 1),
    ("docs/three_d.md", "| 2 | {} s | 0.3976 m", REST_2, "stop_time_s", ".3f", 1),
    ("docs/three_d.md", "| 2 | 0.589 s | {} m, 0.3575 m", REST_2, "runout_centre_m", ".4f", 1),
    ("docs/three_d.md", "| 0.3976 m, {} m | 688", REST_2, "runout_wall_m", ".4f", 1),
    ("docs/three_d.md", "m | {} | 2,034 | 11 |", REST_2, "steps", ",d", 1),
    ("docs/three_d.md", "| 688 | {} | 11 | 457 s", REST_2, "nonlinear_iterations", ",d", 1),
    ("docs/three_d.md", "| 2,034 | {} | 457 s", REST_2, "remeshes", "d", 1),
    ("docs/three_d.md", "| 11 | {} s (both ranks)", REST_2, "cpu_s", ".0f", 1),
    ("docs/three_d.md", "(both ranks) | {} s | 9.0", REST_2, "wall_s", ".0f", 1),
    ("docs/three_d.md", "| 737 s | {}, 13.9 |", REST_2, lambda d: d["load_average"][0], ".1f", 1),
    ("docs/three_d.md", "| 9.0, {} | 663 MB", REST_2, lambda d: d["load_average"][3], ".1f", 1),
    ("docs/three_d.md", ", 13.9 | {} MB |", REST_2, "peak_mb", ".0f", 1),
    ("docs/three_d.md", "at the wall: {} cm shorter", REST_1,
     lambda d: d["runout_centre_m"] - d["runout_wall_m"], ".1f", 100),
    ("docs/three_d.md", "top rises {} mm", REST_1, lambda d: d["wall_height_m"] - 0.14,
     ".1f", 1e3),
    ("docs/three_d.md", "({} m against the column's", REST_1, "wall_height_m", ".4f", 1),
    ("docs/three_d.md", "stopped at {} s after 1,309 steps", REST_1_OLD, "stop_time_s", ".3f",
     1),
    ("docs/three_d.md", "s after {} steps in 291", REST_1_OLD, "steps", ",d", 1),
    ("docs/three_d.md", "steps in {} processor\nseconds on one rank", REST_1_OLD, "cpu_s",
     ".0f", 1),
    ("docs/three_d.md", "seconds on one rank and {} on two", REST_2_OLD, "cpu_s", ".0f", 1),
    ("docs/three_d.md", "apart: {} % in the stop\ntime", REST_2, _apart("stop_time_s"), ".1f",
     1),
    ("docs/three_d.md", "{} % in the centre-line runout", REST_2, _apart("runout_centre_m"),
     ".1f", 1),
    ("docs/three_d.md", "{} % at the wall. Two ranks", REST_2, _apart("runout_wall_m"), ".1f",
     1),
    ("docs/three_d.md", "Two ranks cost {} times the", REST_2,
     lambda d: d["cpu_s"] / json.loads((RESULTS / REST_1).read_text())["cpu_s"], ".1f", 1),
    ("docs/three_d.md", "own time, of the {} s)", REST_1, "cpu_s", ".0f", 1),
    ("docs/three_d.md", "but the processor time, {} s\nthen.)", REST_1_323, "cpu_s", ".0f", 1),
    ("docs/three_d.md", "solves {} s (22 %", REST_1, _own("_call_pardiso"), ".0f", 1),
    ("docs/three_d.md", "calls), Netgen's meshing {} s", REST_1, _own("GenerateMesh"), ".0f", 1),
    ("docs/three_d.md", "solves 26 s ({} %", REST_1,
     lambda d: 100 * _own("_call_pardiso")(d) / d["cpu_s"], ".0f", 1),
    ("docs/three_d.md", "(22 %, {} calls)", REST_1,
     lambda d: next(r["calls"] for r in d["profile"] if "_call_pardiso" in r["function"]),
     ",d", 1),
    ("docs/three_d.md", "\n({} %, 15 calls", REST_1,
     lambda d: 100 * _own("GenerateMesh")(d) / d["cpu_s"], ".0f", 1),
    ("docs/three_d.md", "(14 %, {} calls: the first", REST_1,
     lambda d: next(r["calls"] for r in d["profile"] if "GenerateMesh" in r["function"]),
     "d", 1),
    ("docs/three_d.md", "assembly {} s", REST_1, _own("comp.Assemble"), ".1f", 1),
    ("docs/three_d.md", "remesh {} s (", REST_1, _own("plane_section"), ".1f", 1),
    ("docs/three_d.md", "({} s with what they call)", REST_1,
     lambda d: next(r["cumulative_s"] for r in d["profile"]
                    if "plane_section" in r["function"]), ".1f", 1),
    ("docs/three_d.md", "(`--size 0.02`: runout {} %", PLANE_20, "runout_relative", "+.2f",
     100),
    ("docs/three_d.md", "and {} mm apart behind the", PLANE_20,
     _at("surface_distance_behind_front_max_m", "0.2"), ".2f", 1e3),
    ("docs/three_d.md", "the contact on the back wall, {} mm below the 2D", PLANE_20_OLD,
     _at("surface_distance_behind_front_max_m", "0.2"), ".1f", 1e3),
    # --- the 10 cm channel against 2D, and the 3D rest stop (three_d_collapse.py channel,
    #     three_d_creep.py)
    ("docs/three_d.md", "| runout | {} m | 0.3971 m", CHANNEL, "runs.2d.runout_m", ".4f", 1),
    ("docs/three_d.md", "| 0.3902 m | {} m (+1.8 %)", CHANNEL, "runs.3d.runout_centre_m",
     ".4f", 1),
    ("docs/three_d.md", "0.3971 m ({} %) |", CHANNEL, "runout_centre_relative", "+.1f", 100),
    ("docs/three_d.md", "| {} m (-11.3 %) |", CHANNEL, "runs.3d.runout_wall_m", ".4f", 1),
    ("docs/three_d.md", "0.3461 m ({} %) |", CHANNEL, "runout_wall_relative", "+.1f", 100),
    ("docs/three_d.md", "| {} s | 0.411 s |", CHANNEL, "runs.2d.front_settle_time_s", ".3f", 1),
    ("docs/three_d.md", "| 0.399 s | {} s | |", CHANNEL, "runs.3d.front_settle_time_s", ".3f",
     1),
    ("docs/three_d.md", "| {} s | 0.571 s |", CHANNEL, "runs.2d.stop_time_s", ".3f", 1),
    ("docs/three_d.md", "| 0.491 s | {} s | |", CHANNEL, "runs.3d.stop_time_s", ".3f", 1),
    ("docs/three_d.md", "2D surface lies within {} mm of the 3D", CHANNEL,
     _surfaces_max("centre", "distance_behind_front_max_m"), ".1f", 1e3),
    ("docs/three_d.md", "and within {} mm of the wall's", CHANNEL,
     _surfaces_max("wall", "distance_behind_front_max_m"), ".1f", 1e3),
    ("docs/three_d.md", "mean height differences are at most {} mm", CHANNEL,
     lambda d: max(abs(g[side]["height_difference_mean_m"]) for g in d["surfaces"].values()
                   for side in ("centre", "wall")), ".2f", 1e3),
    ("docs/three_d.md", "walls hold back by {} cm", CHANNEL,
     lambda d: d["runs"]["3d"]["runout_centre_m"] - d["runs"]["3d"]["runout_wall_m"], ".1f",
     100),
    ("docs/three_d.md", "surface is up to {} mm from the 2D one", CHANNEL,
     _surfaces_max("wall", "distance_max_m"), ".0f", 1e3),
    ("docs/three_d.md", "(the centre's up to {} mm)", CHANNEL,
     _surfaces_max("centre", "distance_max_m"), ".1f", 1e3),
    ("docs/three_d.md", "(0.5 mm slack) on {} to 76", CHANNEL,
     lambda d: min(g["between_share"] for g in d["surfaces"].values()), ".0f", 100),
    ("docs/three_d.md", "on 43 to {} % of their common", CHANNEL,
     lambda d: max(g["between_share"] for g in d["surfaces"].values()), ".0f", 100),
    ("docs/three_d.md", "the stop is {} % later in 3D", CHANNEL,
     lambda d: d["runs"]["3d"]["stop_time_s"] / d["runs"]["2d"]["stop_time_s"] - 1, ".0f",
     100),
    ("docs/three_d.md", "the front settles {} ms later", CHANNEL,
     lambda d: d["runs"]["3d"]["front_settle_time_s"] - d["runs"]["2d"]["front_settle_time_s"],
     ".0f", 1e3),
    ("docs/three_d.md", "({} of its volume still above 1 mm/s", CREEP,
     _snapshot(RUN_3D, 0.53, "flowing_share"), ".2f", 1),
    ("docs/three_d.md", "above 1 mm/s\nat {} s, after the 2D", CREEP, _snapshot(RUN_3D, 0.53, "t"),
     ".2f", 1),
    ("docs/three_d.md", "ae713bc and stopped at\n{} s;", REST_1_OLD, "stop_time_s", ".3f", 1),
    ("docs/three_d.md", "digit (at rest at {} s, with", CHANNEL, "runs.3d.stop_time_s",
     ".3f", 1),
    ("docs/three_d.md", "digit (at rest at {} s, with", REST_1, "stop_time_s", ".3f", 1),
    ("docs/three_d.md", "runouts of {} m on the centre line and 0.3461", CHANNEL,
     "runs.3d.runout_centre_m", ".4f", 1),
    ("docs/three_d.md", "runouts of {} m on the centre line and 0.3461", REST_1,
     "runout_centre_m", ".4f", 1),
    ("docs/three_d.md", "and {} m at the wall, in 669", CHANNEL, "runs.3d.runout_wall_m",
     ".4f", 1),
    ("docs/three_d.md", "and {} m at the wall, in 669", REST_1, "runout_wall_m", ".4f", 1),
    ("docs/three_d.md", "at the wall, in {} steps).", CHANNEL, "runs.3d.steps", "d", 1),
    ("docs/three_d.md", "at the wall, in {} steps).", REST_1, "steps", "d", 1),
    ("docs/three_d.md", "_ea5e448.json`), stopped at {} s", CHANNEL_OLD,
     "runs.3d.stop_time_s", ".3f", 1),
    ("docs/three_d.md", "with the wall's runout at {} m; the 2D", CHANNEL_OLD,
     "runs.3d.runout_wall_m", ".4f", 1),
    ("docs/three_d.md", "the stop, {} % after the 2D one in the earlier", CHANNEL_OLD,
     lambda d: d["runs"]["3d"]["stop_time_s"] / d["runs"]["2d"]["stop_time_s"] - 1, ".0f",
     100),
    ("docs/three_d.md", "is now {} % after it", CHANNEL,
     lambda d: d["runs"]["3d"]["stop_time_s"] / d["runs"]["2d"]["stop_time_s"] - 1, ".0f",
     100),
    ("docs/three_d.md", "({} % against 53 % at the least)", CHANNEL,
     lambda d: min(g["between_share"] for g in d["surfaces"].values()), ".0f", 100),
    ("docs/three_d.md", "(43 % against {} % at the least)", CHANNEL_OLD,
     lambda d: min(g["between_share"] for g in d["surfaces"].values()), ".0f", 100),
    ("docs/three_d.md", "the earlier code between {} and", CREEP_OLD,
     lambda d: d[RUN_3D]["snapshots"][0]["t"], ".2f", 1),
    ("docs/three_d.md", "between 0.60 and {} s, `creep.json`", CREEP_OLD,
     lambda d: d[RUN_3D]["snapshots"][-1]["t"], ".2f", 1),
    ("docs/three_d.md", "**Where**: at {} s and 0.84 s", CREEP_OLD,
     _snapshot(RUN_3D, 0.60, "t"), ".2f", 1),
    ("docs/three_d.md", "at 0.60 s and {} s of the earlier", CREEP_OLD,
     _snapshot(RUN_3D, 0.84, "t"), ".2f", 1),
    ("docs/three_d.md", "slivers whose share, {} % here", CREEP, _last(RUN_3D, "flowing_share"),
     ".3f", 100),
    ("docs/three_d.md", "here\n  and {} to 0.29 %", CREEP_OLD,
     _snapshot(RUN_3D, 0.84, "flowing_share"), ".2f", 100),
    ("docs/three_d.md", "and 0.13 to {} % in the earlier run", CREEP_OLD,
     _snapshot(RUN_3D, 0.60, "flowing_share"), ".2f", 100),
    ("docs/three_d.md", "run again, gives it to the digit ({} s,", CREEP_OLD,
     lambda d: d[RUN_3D]["stop_time_s"], ".3f", 1),
    ("docs/three_d.md", "to the digit (0.883 s, {} steps)", CREEP_OLD, lambda d: d[RUN_3D]["steps"],
     ",d", 1),
    ("docs/three_d.md", "run above stops at {} s, the two runs", CHANNEL, "runs.3d.stop_time_s",
     ".3f", 1),
    ("docs/three_d.md", "earlier run, {} and 36 small cells", CREEP_OLD,
     _snapshot(RUN_3D, 0.60, "flowing_cells"), ".0f", 1),
    ("docs/three_d.md", "62 and {} small cells", CREEP_OLD,
     _snapshot(RUN_3D, 0.84, "flowing_cells"), ".0f", 1),
    ("docs/three_d.md", "small cells, {} % and", CREEP_OLD,
     _snapshot(RUN_3D, 0.60, "flowing_share"), ".2f", 100),
    ("docs/three_d.md", "0.29 % and\n  {} % of the volume", CREEP_OLD,
     _snapshot(RUN_3D, 0.84, "flowing_share"), ".2f", 100),
    ("docs/three_d.md", "flowing at {} and 5.6 mm/s", CREEP_OLD,
     _snapshot(RUN_3D, 0.60, "max_speed_m_s"), ".1f", 1e3),
    ("docs/three_d.md", "flowing at 8.4 and {} mm/s", CREEP_OLD,
     _snapshot(RUN_3D, 0.84, "max_speed_m_s"), ".1f", 1e3),
    ("docs/three_d.md", "the fastest at x = {} and", CREEP_OLD,
     _snapshot(RUN_3D, 0.60, lambda r: r["fastest_at_m"][0]), ".3f", 1),
    ("docs/three_d.md", "0.325 and\n  {} m (the wall's", CREEP_OLD,
     _snapshot(RUN_3D, 0.84, lambda r: r["fastest_at_m"][0]), ".3f", 1),
    ("docs/three_d.md", "(the wall's front at {} m)", CREEP_OLD,
     lambda d: d[RUN_3D]["runout_wall_m"], ".3f", 1),
    ("docs/three_d.md", "{} mm from the side wall and", CREEP_OLD,
     _snapshot(RUN_3D, 0.60, lambda r: 0.05 - r["fastest_at_m"][1]), ".1f", 1e3),
    ("docs/three_d.md", "side wall and {} and 2.9 mm", CREEP_OLD,
     _snapshot(RUN_3D, 0.60, lambda r: r["fastest_at_m"][2]), ".1f", 1e3),
    ("docs/three_d.md", "12.6 and {} mm\n  above the bed", CREEP_OLD,
     _snapshot(RUN_3D, 0.84, lambda r: r["fastest_at_m"][2]), ".1f", 1e3),
    ("docs/three_d.md", "free surface ({} and 76 %", CREEP_OLD,
     _snapshot(RUN_3D, 0.60, "on_free_surface"), ".0f", 100),
    ("docs/three_d.md", "(67 and {} % of their volume)", CREEP_OLD,
     _snapshot(RUN_3D, 0.84, "on_free_surface"), ".0f", 100),
    ("docs/three_d.md", "mean pressure of {} and 29 Pa", CREEP_OLD,
     _snapshot(RUN_3D, 0.60, "pressure_mean_pa"), ".0f", 1),
    ("docs/three_d.md", "of 32 and {} Pa", CREEP_OLD,
     _snapshot(RUN_3D, 0.84, "pressure_mean_pa"), ".0f", 1),
    ("docs/three_d.md", "(mean yield ratio {} and", CREEP_OLD,
     _snapshot(RUN_3D, 0.60, "yield_ratio_mean"), ".2f", 1),
    ("docs/three_d.md", "ratio 1.17 and {})", CREEP_OLD,
     _snapshot(RUN_3D, 0.84, "yield_ratio_mean"), ".2f", 1),
    ("docs/three_d.md", "half of their speed ({} and 57 %)", CREEP_OLD,
     _snapshot(RUN_3D, 0.60, "across_share"), ".0f", 100),
    ("docs/three_d.md", "speed (56 and {} %)", CREEP_OLD,
     _snapshot(RUN_3D, 0.84, "across_share"), ".0f", 100),
    ("docs/three_d.md", "(a mean {} and 1.7 mm/s)", CREEP_OLD,
     _snapshot(RUN_3D, 0.60, "across_mean_m_s"), ".1f", 1e3),
    ("docs/three_d.md", "mean 2.4 and {} mm/s)", CREEP_OLD,
     _snapshot(RUN_3D, 0.84, "across_mean_m_s"), ".1f", 1e3),
    ("docs/three_d.md", "edge keeps {} cells at", CREEP, _last(RUN_3D, "flowing_cells"), "d",
     1),
    ("docs/three_d.md", "cells at {} mm/s, 0.037 %", CREEP, _last(RUN_3D, "max_speed_m_s"),
     ".1f", 1e3),
    ("docs/three_d.md", "4.3 mm/s, {} % of the", CREEP, _last(RUN_3D, "flowing_share"), ".3f",
     100),
    ("docs/three_d.md", "(its fastest cell at\n  {} m/s)", CREEP, _last(RUN_2D, "max_speed_m_s"),
     ".0e", 1),
    ("docs/three_d.md", "with `numerics.tol = 1e-8` ({} iterations a step", PROBE,
     "resumed_tol1e-8.window.iterations_per_step", ".0f", 1),
    ("docs/three_d.md", "iterations a step instead of {})", PROBE,
     "resumed_tol3e-4.window.iterations_per_step", ".0f", 1),
    ("docs/three_d.md", "keeps the edge at\n  {} mm/s", PROBE,
     _last("resumed_tol1e-8", "max_speed_m_s"), ".2f", 1e3),
    ("docs/three_d.md", "3e-4 does ({} mm/s)", PROBE, _last("resumed_tol3e-4", "max_speed_m_s"),
     ".2f", 1e3),
    ("docs/three_d.md", "by the equivalent of {} mm/s", CREEP_OLD,
     lambda d: d[RUN_3D]["window"]["volume_correction_surface_speed_m_s"], ".4f", 1e3),
    ("docs/three_d.md", "holds up to {} % of the half", CREEP, _last(RUN_3D, "largest_cell_share"),
     ".1f", 100),
    ("docs/three_d.md", "volume ({} % in the\n  earlier run)", CREEP_OLD,
     _last(RUN_3D, "largest_cell_share"), ".1f", 100),
    ("docs/three_d.md", "earlier run), {} to 20 times", CREEP, _last(RUN_3D, "largest_cell_share"),
     ".0f", 1e3),
    ("docs/three_d.md", "12 to {} times the fraction", CREEP_OLD,
     _last(RUN_3D, "largest_cell_share"), ".0f", 1e3),
    ("docs/three_d.md", "one of the 2D run's {} triangles", CREEP, _last(RUN_2D, "cells"), "d", 1),
    ("docs/three_d.md", "triangles up to\n  {} % of the section", CREEP,
     _last(RUN_2D, "largest_cell_share"), ".1f", 100),
    ("docs/three_d.md", "| runout | {} m | 1.1404", SLOPE19, "runs.2d.runout_m", ".4f", 1),
    ("docs/three_d.md", "| {} m (+4.1 %) |", SLOPE19, "runs.3d.runout_centre_m", ".4f", 1),
    ("docs/three_d.md", "1.1404 m (+{} %) |", SLOPE19, "runout_centre_relative", ".1f", 100),
    ("docs/three_d.md", "| {} m (-4.3 %) |", SLOPE19, "runs.3d.runout_wall_m", ".4f", 1),
    ("docs/three_d.md", "1.0486 m (-{} %) |", SLOPE19, lambda d: -d["runout_wall_relative"],
     ".1f", 100),
    ("docs/three_d.md", "| the front settles | {} s | 1.359", SLOPE19,
     "runs.2d.front_settle_time_s", ".3f", 1),
    ("docs/three_d.md", "| 1.296 s | {} s | |", SLOPE19, "runs.3d.front_settle_time_s", ".3f",
     1),
    ("docs/three_d.md", "| at rest | {} s | 1.385", SLOPE19, "runs.2d.stop_time_s", ".3f", 1),
    ("docs/three_d.md", "| 1.320 s | {} s | |", SLOPE19, "runs.3d.stop_time_s", ".3f", 1),
    ("docs/three_d.md", "and its runout is {} % short", SLOPE19,
     lambda d: 1 - d["runs"]["2d"]["runout_m"] / ERODIBLE_19_RUNOUT, ".0f", 100),
    ("docs/three_d.md", "the centre line runs {} % further", SLOPE19, "runout_centre_relative",
     ".1f", 100),
    ("docs/three_d.md", "and the wall {} % less far", SLOPE19,
     lambda d: -d["runout_wall_relative"], ".1f", 100),
    ("docs/three_d.md", "The front settles\n{} % later", SLOPE19,
     lambda d: d["runs"]["3d"]["front_settle_time_s"] / d["runs"]["2d"]["front_settle_time_s"]
     - 1, ".1f", 100),
    ("docs/three_d.md", "comes to rest {} % later", SLOPE19,
     lambda d: d["runs"]["3d"]["stop_time_s"] / d["runs"]["2d"]["stop_time_s"] - 1, ".1f",
     100),
    ("docs/three_d.md", "surface lies within {} mm of the 3D centre-line", SLOPE19,
     _surfaces_max("centre", "distance_behind_front_max_m"), ".1f", 1e3),
    ("docs/three_d.md", "and {} mm of the wall's at the output times and at rest", SLOPE19,
     _surfaces_max("wall", "distance_behind_front_max_m"), ".1f", 1e3),
    ("docs/three_d.md", "differences\nare at most {} mm. The 3D front", SLOPE19,
     lambda d: max(abs(g[side]["height_difference_mean_m"]) for g in d["surfaces"].values()
                   for side in ("centre", "wall")), ".2f", 1e3),
    ("docs/three_d.md", "centre line {} % behind at the second output time", SLOPE19,
     lambda d: -(d["surfaces"]["0.300"]["centre"]["front_x_m"]
                 / d["surfaces"]["0.300"]["front_x_2d_m"] - 1), ".1f", 100),
    ("docs/three_d.md", "The 3D run took {} steps and", SLOPE19, "runs.3d.steps", ",d", 1),
    ("docs/three_d.md", "steps and {} s of processor time (the", SLOPE19, "runs.3d.cpu_s",
     ".0f", 1),
    ("docs/three_d.md", "`channel_h0.04_slope19_b6a2d0e.json`, {} s of processor", SLOPE19_OLD,
     "runs.3d.cpu_s", ".0f", 1),
    ("docs/three_d.md", "but the processor time ({} s against 92 s)", CHANNEL, "runs.3d.cpu_s",
     ".0f", 1),
    ("docs/three_d.md", "processor time (110 s against {} s)", CHANNEL_7A, "runs.3d.cpu_s",
     ".0f", 1),
    ("docs/three_d.md", "stopped at {} s after\n1,533", SLOPE19_CROSSING, "runs.3d.t_final",
     ".3f", 1),
    ("docs/three_d.md", "after\n{} steps (`channel_h0.04_slope19_crossing", SLOPE19_CROSSING,
     "runs.3d.steps", ",d", 1),
    ("docs/three_d.md", "free surfaces {} m apart", MAIN_VS_3D, _largest_surface_gap,
     ".1f", 1),
    # --- the packing fraction (benchmarks/packing.py)
    ("docs/verification.md", "runouts 0.4250 / {} m", PACKING, "rows.dense.runout_m",
     ".4f", 1),
    ("docs/verification.md", "at rest at 0.569 / {} s", PACKING, "rows.dense.stop_time_s",
     ".3f", 1),
    ("docs/verification.md", "runs 0.4250 and {} m", PACKING, "rows.dense.runout_m",
     ".4f", 1),
    ("docs/verification.md", "(incompressible {} m)", PACKING,
     "rows.incompressible.runout_m", ".4f", 1),
    ("docs/verification.md", "at 0.569 and {} s", PACKING, "rows.dense.stop_time_s",
     ".3f", 1),
    ("docs/verification.md", "({} s), its volume", PACKING,
     "rows.incompressible.stop_time_s", ".3f", 1),
    ("docs/verification.md", "-1.85 % and +{} %", PACKING,
     "rows.dense.volume_relative_error", ".2f", 100),
    ("docs/verification.md", "the dense rectangle to {} s", PACKING_COST, "t_end", ".2f", 1),
    ("docs/verification.md", "x 1.23 ({} s against", PACKING_COST, _step_cost("dense"),
     ".4f", 1),
    ("docs/verification.md", "s against {} s, load", PACKING_COST,
     _step_cost("incompressible"), ".4f", 1),
    # --- the tracking's step, part by part (benchmarks/layer_tracking_step.py)
    ("docs/performance.md", "at 0.3 s a step's tracking took {} ms before", STEP_BEFORE,
     _step("0.3"), ".2f", 1),
    ("docs/performance.md", "ms before and {} ms now (the sample", STEP_AFTER,
     _step("0.3"), ".2f", 1),
    ("docs/performance.md", "now (the sample {} ->", STEP_BEFORE,
     _step("0.3", "sample"), ".2f", 1),
    ("docs/performance.md", "-> {} ms); at 0.6 s", STEP_AFTER,
     _step("0.3", "sample"), ".2f", 1),
    ("docs/performance.md", "outside the mesh, {} and", STEP_BEFORE,
     _step("0.6"), ".2f", 1),
    ("docs/performance.md", "and {} ms (the sample 3", STEP_AFTER,
     _step("0.6"), ".2f", 1),
    ("docs/performance.md", "ms (the sample {} -> 2", STEP_BEFORE,
     _step("0.6", "sample"), ".2f", 1),
    ("docs/performance.md", "-> {} ms). The measures", STEP_AFTER,
     _step("0.6", "sample"), ".2f", 1),
    ("docs/performance.md", "the erosion figure included) at {} % and", PROFILE_BEFORE,
     "shares.erodible layer tracking", ".1f", 100),
    ("docs/performance.md", "% and {} % of the process. Three rounds", PROFILE_AFTER,
     "shares.erodible layer tracking", ".1f", 100),
    ("docs/performance.md", "`trapezoid-rigid` {} s and `trapezoid-erodible`", TRACKING_PAIR,
     "trapezoid.stats.quiet.cpu_s.first", ".1f", 1),
    ("docs/performance.md", "`trapezoid-erodible` {} s of processor time,", TRACKING_PAIR,
     "trapezoid.stats.quiet.cpu_s.second", ".1f", 1),
    ("docs/performance.md", "processor time, ratio {}, as on the nearly idle", TRACKING_PAIR,
     "trapezoid.stats.quiet.cpu_ratio", ".2f", 1),
    ("docs/performance.md", "tracking-baseline/`): {} s and", TRACKING_BASE,
     "baseline.stats.quiet.cpu_s.first", ".1f", 1),
    ("docs/performance.md", "s and {} s, ratio 0", TRACKING_BASE,
     "baseline.stats.quiet.cpu_s.second", ".1f", 1),
    ("docs/performance.md", "s, ratio {}, the rounds' ratios", TRACKING_BASE,
     "baseline.stats.quiet.cpu_ratio", ".2f", 1),
    ("docs/performance.md", "spreading from {} to", TRACKING_BASE,
     lambda d: min(b["process_cpu_time_s"] / a["process_cpu_time_s"] for a, b in zip(
         d["baseline"]["runs"]["quiet"]["first"], d["baseline"]["runs"]["quiet"]["second"],
         strict=True)), ".2f", 1),
    ("docs/performance.md", "from 0.87 to {}.", TRACKING_BASE,
     lambda d: max(b["process_cpu_time_s"] / a["process_cpu_time_s"] for a, b in zip(
         d["baseline"]["runs"]["quiet"]["first"], d["baseline"]["runs"]["quiet"]["second"],
         strict=True)), ".2f", 1),
    ("CHANGELOG.md", "`trapezoid-erodible`: {} -> 3", STEP_BEFORE, _step("0.3"), ".2f", 1),
    ("CHANGELOG.md", "-> {} ms at 0.3 s", STEP_AFTER, _step("0.3"), ".2f", 1),
    ("CHANGELOG.md", "at 0.3 s and {} -> 5", STEP_BEFORE, _step("0.6"), ".2f", 1),
    ("CHANGELOG.md", "-> {} ms at 0.6 s", STEP_AFTER, _step("0.6"), ".2f", 1),
    # --- the erodible bed on the user's clock (benchmarks/erodible_speed.py and py-spy)
    ("docs/performance.md", "the tracking fell from {} % to",
     "profile_shares/trapezoid-erodible-284e367.json", "shares.erodible layer tracking",
     ".1f", 100),
    ("docs/performance.md", "% to {} % of the process; a flow over a layer",
     "profile_shares/trapezoid-erodible-cc22b00.json", "shares.erodible layer tracking",
     ".1f", 100),
    ("docs/performance.md", "rest rule from {} to", ERODIBLE_SPEED,
     _stop("base-vs-head", "trapezoid-rigid", 0), ".4f", 1),
    ("docs/performance.md", "to {} s.\n\nThe remeshes are not yet", ERODIBLE_SPEED,
     _stop("base-vs-head", "trapezoid-rigid", 1), ".4f", 1),
    ("docs/performance.md", "[The time integrator](#the-time-integrator) (1 and {} mm)",
     ERODIBLE_SPEED, "criteria.surface_max_mm", ".0f", 1),
    ("docs/performance.md", "The cylinder's rest rule moves by {} %: it is decided",
     ERODIBLE_SPEED, _stop_change("head-vs-slow", "cylinder-erodible"), ".0f", 1),
    # --- the slope study's 22-degree row with the slow flow's cap (slope22_steps.py, py-spy)
    ("docs/performance.md", "`benchmarks/results/slope22_steps/slope22_steps.md`): {} s of",
     SLOPE22_PAIR, "runs.dt_max.process_cpu_time_s", ".0f", 1),
    ("docs/performance.md", "and {} s with the cap. With", SLOPE22_PAIR,
     "runs.slow.process_cpu_time_s", ".0f", 1),
    ("docs/performance.md", "the runout changes by {} %, the layer", SLOPE22_PAIR,
     "changes.slow.changes_percent.runout_m", ".2f", 1),
    ("docs/performance.md", "displaced\narea by {} % and", SLOPE22_PAIR,
     "changes.slow.changes_percent.layer_displaced", ".2f", 1),
    ("docs/performance.md", "largest mobilised area by {} %, within", SLOPE22_PAIR,
     "changes.slow.changes_percent.layer_mobilised", ".2f", 1),
    ("docs/performance.md", "at 0.5 s are {} mm apart on average", SLOPE22_PAIR,
     "changes.slow.surfaces_mm.surface_mean_mm", ".2f", 1),
    ("docs/performance.md", "on average and {} mm at most", SLOPE22_PAIR,
     "changes.slow.surfaces_mm.surface_max_mm", ".1f", 1),
    ("docs/performance.md", "and stopped at t = {} s, before", SLOPE22_RUN, "t_s", ".2f", 1),
    ("docs/performance.md", "The cap raised {} of its", SLOPE22_RUN, "steps_above_dt_max",
     ",d", 1),
    ("docs/performance.md", "of its {} steps, all in the", SLOPE22_RUN, "steps", ",d", 1),
    ("docs/performance.md", "all in the first {} s, while", SLOPE22_RUN,
     "last_step_above_dt_max_t_s", ".3f", 1),
    ("docs/performance.md", "the beads keep {} % of the section", SLOPE22_RUN,
     "flowing_fraction_last", ".0f", 100),
    ("docs/performance.md", "flowing at {} s (`python benchmarks/slope22_steps.py", SLOPE22_RUN,
     "t_s", ".2f", 1),
    ("docs/performance.md", "py-spy over those {} s", SLOPE22_RUN, "t_s", ".2f", 1),
    ("docs/performance.md", "the factorisation of (3.2) is {} % of the process", SLOPE22_PROFILE,
     _share("factorisation (sparse LU)"), ".1f", 100),
    ("docs/performance.md", "and its assembly {} %, remeshing", SLOPE22_PROFILE,
     _share("assembly (matrix and right-hand side of (3.2))"), ".1f", 100),
    ("docs/performance.md", "the state's transfer {} % (the moves", SLOPE22_PROFILE,
     _share("remeshing and transfer"), ".1f", 100),
    ("docs/performance.md", "remeshed before the step, {} %:", SLOPE22_PROFILE,
     "remeshed_ahead", ".1f", 100),
    ("docs/performance.md", "%: {} of its 237 remeshes", SLOPE22_RUN, "remeshed_moves", ",d", 1),
    ("docs/performance.md", "of its {} remeshes), the layer's", SLOPE22_RUN, "remeshes", ",d",
     1),
    ("docs/performance.md", "the layer's tracking {} %. The remeshes", SLOPE22_PROFILE,
     _share("erodible layer tracking"), ".1f", 100),
    # --- the erodible cylinder's rest stop under MKL's two modes (collapse_runs.py, rest_creep.py)
    ("docs/performance.md", "cylinder-erodible` rests at {} s (445 steps)", CYL_AUTO,
     f"{CYL}.stop_time_s", ".2f", 1),
    ("docs/performance.md", "rests at 0.81 s ({} steps); with", CYL_AUTO, f"{CYL}.steps",
     ",d", 1),
    ("docs/performance.md", "the table's, at {} s (483 steps)", CYL_COMPAT,
     f"{CYL}.stop_time_s", ".2f", 1),
    ("docs/performance.md", "the table's, at 1.15 s ({} steps)", CYL_COMPAT, f"{CYL}.steps",
     ",d", 1),
    ("docs/performance.md", "section) at {} s in both", CYL_PAIR,
     f"{CYL}.cyl-auto.duration_s", ".3f", 1),
    ("docs/performance.md", "s in both ({} %), the", CYL_PAIR,
     f"{CYL}.relative_changes.duration_s", ".2f", 100),
    ("docs/performance.md", "within {} mm of each other on average", CYL_PAIR,
     _surfaces("mean_m"), ".2f", 1e3),
    ("docs/performance.md", "on average and {} mm at most (early", CYL_PAIR, _surfaces("max_m"),
     ".1f", 1e3),
    ("docs/performance.md", "folding nose; {} mm at 0.8 s)", CYL_PAIR,
     lambda d: d[CYL]["free_surfaces"]["0.800"]["max_m"], ".2f", 1e3),
    ("docs/performance.md", "the runout is {} % shorter", CYL_PAIR,
     lambda d: -d[CYL]["relative_changes"]["runout_m"], ".2f", 100),
    ("docs/performance.md", "({} against 241.0 mm)", CYL_AUTO, f"{CYL}.runout_m", ".1f", 1e3),
    ("docs/performance.md", "(239.7 against {} mm)", CYL_COMPAT, f"{CYL}.runout_m", ".1f",
     1e3),
    ("docs/performance.md", "the foot crept {} s less", CYL_CREEP,
     lambda d: _creep("compat", "stop_time_s")(d) - _creep("auto", "stop_time_s")(d), ".2f", 1),
    ("docs/performance.md", "(largest speed {} mm/s at 0.80-0.85 s)", CYL_CREEP,
     _window_speed("auto", 0.8), ".2f", 1e3),
    ("docs/performance.md", "crosses the threshold at {} s; with", CYL_CREEP,
     _creep("auto", "stop_time_s"), ".2f", 1),
    ("docs/performance.md", "and crosses it only at {} s.", CYL_CREEP,
     _creep("compat", "stop_time_s"), ".2f", 1),
    ("docs/verification.md", "runs out to r∞ = {} m with", CYL_AUTO, f"{CYL}.runout_m", ".4f", 1),
    ("docs/verification.md", "m with {} m on the axis", CYL_AUTO, f"{CYL}.wall_height_m",
     ".3f", 1),
    ("docs/verification.md", "on the axis ({} steps, 57 remeshes)", CYL_AUTO, f"{CYL}.steps",
     ",d", 1),
    ("docs/verification.md", "steps, {} remeshes); its flow ends", CYL_AUTO, f"{CYL}.remeshes",
     ",d", 1),
    ("docs/verification.md", "`duration_s`) at {} s. After that", CYL_PAIR,
     f"{CYL}.cyl-auto.duration_s", ".3f", 1),
    ("docs/verification.md", "0.1 %: {} s with MKL's own kernels", CYL_AUTO,
     f"{CYL}.stop_time_s", ".2f", 1),
    ("docs/verification.md", "kernels (the default) and {} s with", CYL_COMPAT,
     f"{CYL}.stop_time_s", ".2f", 1),
    ("docs/verification.md", "(r∞ = {} m), the same flow otherwise", CYL_COMPAT,
     f"{CYL}.runout_m", ".4f", 1),
    # --- the slab and the rigid bed's models (benchmarks/slab.py, benchmarks/bed_models.py)
    ("docs/erosion.md", r"| **no-slip bed and \(\eta\) = 0.01: drucker-prager** | **{}** |",
     SLAB, _slab_ratio("drucker-prager/no-slip+small-eta", 0), ".2f", 1),
    ("docs/erosion.md", r"| **no-slip and \(\eta\) = 0.01: glass-beads** | **{}** |", SLAB,
     _slab_ratio("glass-beads/no-slip+small-eta", 0), ".2f", 1),
    ("docs/erosion.md", r"| **no-slip and \(\eta\) = 0.01: nonlocal** | **{}** |", SLAB,
     _slab_ratio("nonlocal/no-slip+small-eta", 0), ".2f", 1),
    ("docs/erosion.md",
     r"| drucker-prager (Coulomb bed, \(\eta\) = 1 Pa s, 2.5 mm cells) | {} |", SLAB,
     _slab_ratio("drucker-prager", 0), ".2f", 1),
    # the layer's packing (d)
    ("docs/erosion.md",
     r"| (d) no-slip and \(\eta\) = 0.01, layer at \(\phi_c\) / loose / dense: "
     r"drucker-prager | {} /", SLAB,
     _slab_ratio("drucker-prager/no-slip+small-eta+critical-layer", 0), ".2f", 1),
    ("docs/erosion.md",
     r"| (d) no-slip and \(\eta\) = 0.01, layer at \(\phi_c\) / loose / dense: "
     r"glass-beads | {} /", SLAB,
     _slab_ratio("glass-beads/no-slip+small-eta+critical-layer", 0), ".2f", 1),
    ("docs/erosion.md",
     r"| (d) no-slip and \(\eta\) = 0.01, layer at \(\phi_c\) / loose / dense: "
     r"hysteretic | {} /", SLAB,
     _slab_ratio("hysteretic/no-slip+small-eta+critical-layer", 0), ".2f", 1),
    ("docs/erosion.md",
     r"| (d) no-slip and \(\eta\) = 0.01, layer at \(\phi_c\) / loose / dense: "
     r"nonlocal | {} /", SLAB,
     _slab_ratio("nonlocal/no-slip+small-eta+critical-layer", 0), ".2f", 1),
    ("docs/erosion.md",
     r"| (d) material bed and \(\eta\) = 0.01, layer at \(\phi_c\) / loose / dense: "
     r"drucker-prager | {} /", SLAB,
     _slab_ratio("drucker-prager/material-bed+small-eta+critical-layer", 0), ".2f", 1),
    ("docs/erosion.md",
     r"| (d) material bed and \(\eta\) = 0.01, layer at \(\phi_c\) / loose / dense: "
     r"glass-beads | {} /", SLAB,
     _slab_ratio("glass-beads/material-bed+small-eta+critical-layer", 0), ".2f", 1),
    ("docs/erosion.md",
     r"| (d) material bed and \(\eta\) = 0.01, layer at \(\phi_c\) / loose / dense: "
     r"hysteretic | {} /", SLAB,
     _slab_ratio("hysteretic/material-bed+small-eta+critical-layer", 0), ".2f", 1),
    ("docs/erosion.md",
     r"| (d) material bed and \(\eta\) = 0.01, layer at \(\phi_c\) / loose / dense: "
     r"nonlocal | {} /", SLAB,
     _slab_ratio("nonlocal/material-bed+small-eta+critical-layer", 0), ".2f", 1),
    ("docs/erosion.md", "1.33 and ≈ 1.72 to 1.12, {} and", SLAB,
     _slab_ratio("hysteretic/no-slip+small-eta+dense-layer", 19), ".2f", 1),
    ("docs/erosion.md", "dense ratio of the distances is {} to", SLAB, _loose_over_dense(min),
     ".3f", 1),
    ("docs/erosion.md", "distances is 0.996 to {} for the other", SLAB, _loose_over_dense(max),
     ".3f", 1),
    ("docs/erosion.md", "`mass_relative_error_max` {} to", SLAB,
     _packed_extreme("mass_relative_error_max", min), ".1e", 1),
    ("docs/erosion.md", "`mass_relative_error_max` 5.5e-3 to {} (predicted", SLAB,
     _packed_extreme("mass_relative_error_max", max), ".1e", 1),
    ("docs/model.md", "runs took {} nonlinear iterations against 3,309", SLAB_FLUIDITY,
     "5mm-zero.nonlinear_iterations", ",d", 1),
    ("docs/verification.md", "| rectangle | glass-beads | material | 0.687 | {} |", BED_MODELS,
     "flat.rectangle-glass-beads-material.runout_m", ".4f", 1),
    ("docs/verification.md", "| rectangle | nonlocal | material | 1.985 | {} |", BED_MODELS,
     "flat.rectangle-nonlocal-material.runout_m", ".4f", 1),
    ("docs/verification.md", "| trapezoid | nonlocal | material | moving at 3 s | {} |",
     BED_MODELS, "flat.trapezoid-nonlocal-material.runout_m", ".4f", 1),
    ("docs/verification.md", "(it runs out {} m)", BED_MODELS, "rest.rest-22-14mm.runout_m",
     ".3f", 1),
    ("docs/verification.md", "3.54, 4.73 and {} mm thick 1, 2 and 5 cm behind the tip",
     BED_MODELS, "rest.rest-22-14mm.thickness_5cm_behind_tip_mm", ".2f", 1),
    ("docs/verification.md", "at 14 mm the run took {} steps", BED_MODELS,
     "rest.rest-22-14mm.steps", ",d", 1),
    ("docs/verification.md", "the surface's nodes {} mm apart", BED_MODELS,
     "rest.rest-22-14mm.surface_spacing_at_tip_mm", ".1f", 1),
    ("docs/verification.md", "| 0.3736 | -{} % |", BED_MODELS,
     _against_paper_model("rectangle-drucker-prager-no-slip"), ".1f", 100),
    ("docs/verification.md", "| 0.4622 | +{} % |", BED_MODELS,
     _against_paper_model("rectangle-glass-beads-coulomb"), ".1f", 100),
    ("docs/verification.md", "| 0.4078 | -{} % |", BED_MODELS,
     _against_paper_model("rectangle-glass-beads-no-slip"), ".1f", 100),
    ("docs/verification.md", "| 0.4303 | +{} % |", BED_MODELS,
     _against_paper_model("rectangle-glass-beads-material"), ".1f", 100),
    ("docs/verification.md", "| 0.4545 | +{} % |", BED_MODELS,
     _against_paper_model("rectangle-nonlocal-coulomb"), ".1f", 100),
    ("docs/verification.md", "| 0.3967 | -{} % |", BED_MODELS,
     _against_paper_model("rectangle-nonlocal-no-slip"), ".1f", 100),
    ("docs/verification.md", "| 0.4251 | -{} % |", BED_MODELS,
     _against_paper_model("rectangle-nonlocal-material"), ".1f", 100),
    ("docs/verification.md", "| 0.6029 | -{} % |", BED_MODELS,
     _against_paper_model("trapezoid-drucker-prager-no-slip"), ".1f", 100),
    ("docs/verification.md", "| 0.7526 | +{} % |", BED_MODELS,
     _against_paper_model("trapezoid-glass-beads-coulomb"), ".1f", 100),
    ("docs/verification.md", "| 0.6748 | +{} % |", BED_MODELS,
     _against_paper_model("trapezoid-glass-beads-no-slip"), ".1f", 100),
    ("docs/verification.md", "| 0.7031 | +{} % |", BED_MODELS,
     _against_paper_model("trapezoid-glass-beads-material"), ".1f", 100),
    ("docs/verification.md", "| 0.7382 | +{} % |", BED_MODELS,
     _against_paper_model("trapezoid-nonlocal-coulomb"), ".1f", 100),
    ("docs/verification.md", "| 0.6573 | -{} % |", BED_MODELS,
     _against_paper_model("trapezoid-nonlocal-no-slip"), ".1f", 100),
    ("docs/verification.md", "| 0.6965 | +{} % |", BED_MODELS,
     _against_paper_model("trapezoid-nonlocal-material"), ".1f", 100),
    # --- the erosion study on the no-slip bed with eta = 0.01 (erosion_slopes.py)
    ("docs/erosion.md", "| rigid bed | {} m, at rest at 0.896 s |", ETA_STUDY,
     _study("0", 0, "runout_m"), ".4f", 1),
    ("docs/erosion.md", "| rigid bed | 0.4833 m, at rest at {} s |", ETA_STUDY,
     _study("0", 0, "stop_time_s"), ".3f", 1),
    ("docs/erosion.md", "| front {} m at 3 s, moving at 41 mm/s |", ETA_STUDY,
     _study("0", 19, "runout_m"), ".3f", 1),
    ("docs/erosion.md", "| front 1.459 m at 3 s, moving at {} mm/s |", ETA_STUDY,
     _study("0", 19, "front_speed_end_m_s"), ".0f", 1000),
    ("docs/erosion.md", "moving at 41 mm/s | failed at {} s |", ETA_STUDY,
     _study("0", 22, "t_final"), ".3f", 1),
    ("docs/erosion.md", "| 5 mm layer | {} m, at rest at 0.874 s: ratio 1.04 |", ETA_STUDY,
     _study("5", 0, "runout_m"), ".4f", 1),
    ("docs/erosion.md", "| 5 mm layer | 0.5036 m, at rest at {} s: ratio 1.04 |", ETA_STUDY,
     _study("5", 0, "stop_time_s"), ".3f", 1),
    ("docs/erosion.md", "at rest at 0.874 s: ratio {} |", ETA_STUDY, _study_ratio("5", 0),
     ".2f", 1),
    ("docs/erosion.md", "| front {} m at 3 s, moving at 15 mm/s: ratio", ETA_STUDY,
     _study("5", 19, "runout_m"), ".3f", 1),
    ("docs/erosion.md", "| front 1.773 m at 3 s, moving at {} mm/s: ratio", ETA_STUDY,
     _study("5", 19, "front_speed_end_m_s"), ".0f", 1000),
    ("docs/erosion.md", "moving at 15 mm/s: ratio ≈ {}, both fronts moving", ETA_STUDY,
     _study_ratio("5", 19), ".2f", 1),
    ("docs/erosion.md", "at 19° it is about {} (predicted", ETA_STUDY,
     _study_ratio("5", 19), ".2f", 1),
    ("docs/erosion.md", "the experiments' sign, about {} over 5 mm", ETA_STUDY,
     _study_ratio("5", 19), ".2f", 1),
    ("docs/erosion.md", "| front {} m when it failed at 2.042 s,", ETA_STUDY,
     _study("5", 22, "runout_m"), ".3f", 1),
    ("docs/erosion.md", "m when it failed at {} s, moving at 0.55 m/s |",
     ETA_STUDY, _study("5", 22, "t_final"), ".3f", 1),
    ("docs/erosion.md", "failed at 2.042 s, moving at {} m/s |",
     ETA_STUDY, _study("5", 22, "front_speed_end_m_s"), ".2f", 1),
    ("docs/erosion.md", "| 19° | +12 | +27 | +42 | -{} | - |", ETA_STUDY,
     lambda d: -_study_gain("5", 19, "0.5")(d), ".0f", 1000),
    ("docs/erosion.md", "the early gain is lost by\n   0.75 s (-{} mm)", ETA_STUDY,
     lambda d: -_study_gain("5", 19, "0.75")(d), ".0f", 1000),
    ("docs/erosion.md", "describe: +{}, +180, +292 and +314 mm", ETA_STUDY,
     _study_gain("5", 19, "1"), ".0f", 1000),
    ("docs/erosion.md", "describe: +2, +{}, +292 and +314 mm", ETA_STUDY,
     _study_gain("5", 19, "1.5"), ".0f", 1000),
    ("docs/erosion.md", "describe: +2, +180, +{} and +314 mm", ETA_STUDY,
     _study_gain("5", 19, "2"), ".0f", 1000),
    ("docs/erosion.md", "describe: +2, +180, +292 and +{} mm at 1, 1.5, 2 and 3 s", ETA_STUDY,
     _study_gain("5", 19, "3"), ".0f", 1000),
    ("docs/erosion.md", "at the end is refuted: {} against 41 mm/s", ETA_STUDY,
     _study("5", 19, "front_speed_end_m_s"), ".0f", 1000),
    ("docs/erosion.md", "at the end is refuted: 15 against {} mm/s", ETA_STUDY,
     _study("0", 19, "front_speed_end_m_s"), ".0f", 1000),
    ("docs/erosion.md", "| 0° | +{} | +3 | +11 | +26 | +20 |", ETA_STUDY,
     _study_gain("5", 0, "0.1"), ".0f", 1000),
    ("docs/erosion.md", "| 0° | +6 | +3 | +11 | +{} | +20 |", ETA_STUDY,
     _study_gain("5", 0, "0.5"), ".0f", 1000),
    ("docs/erosion.md", "| 19° | +12 | +27 | +{} | -32 | - |", ETA_STUDY,
     _study_gain("5", 19, "0.3"), ".0f", 1000),
    ("docs/erosion.md", "| 22° | +12 | +29 | +{} | +15 | - |", ETA_STUDY,
     _study_gain("5", 22, "0.3"), ".0f", 1000),
    ("docs/erosion.md", "| 22° | +12 | +29 | +36 | +{} | - |", ETA_STUDY,
     _study_gain("5", 22, "0.5"), ".0f", 1000),
    ("docs/erosion.md", "shrinks from +{} mm at 0.3 s", ETA_STUDY,
     _study_gain("5", 22, "0.3"), ".0f", 1000),
    ("docs/erosion.md", "+36 mm at 0.3 s to +{} mm at 0.5 s", ETA_STUDY,
     _study_gain("5", 22, "0.5"), ".0f", 1000),
    ("docs/erosion.md", "rigid twin fails at {} s", ETA_STUDY, _study("0", 22, "t_final"),
     ".3f", 1),
    ("docs/erosion.md", "(erosion depth {} mm;", ETA_STUDY,
     _study("5", 0, "erosion_depth_max_m"), ".0f", 1000),
    ("docs/erosion.md", "at most half at 0–10°): {} cm² at 0°", ETA_STUDY,
     _study("5", 0, "layer_displaced_area_m2"), ".1f", 1e4),
    ("docs/erosion.md", "cm² at 0°, {} cm²\n   at 19°", ETA_STUDY,
     _study("5", 19, "layer_displaced_area_m2"), ".1f", 1e4),
    ("docs/erosion.md", "(at 3 s) and {} cm² at 22°", ETA_STUDY,
     _study("5", 22, "layer_displaced_area_m2"), ".1f", 1e4),
    ("docs/erosion.md", "material (0, {} and 0 %", ETA_STUDY,
     _study("5", 19, "displaced_ahead_of_column_share"), ".0f", 100),
    ("docs/erosion.md", "material (0, 1 and {} %", ETA_STUDY,
     _study("5", 22, "displaced_ahead_of_column_share"), ".0f", 100),
    ("docs/erosion.md", "median {} , 7.9 and 14.5 cm".replace(" ,", ","), ETA_STUDY,
     _study("5", 0, "displaced_advance_median_m"), ".1f", 100),
    ("docs/erosion.md", "median 1.0, {} and 14.5 cm", ETA_STUDY,
     _study("5", 19, "displaced_advance_median_m"), ".1f", 100),
    ("docs/erosion.md", "median 1.0, 7.9 and {} cm", ETA_STUDY,
     _study("5", 22, "displaced_advance_median_m"), ".1f", 100),
    ("docs/verification.md", "5 mm: {} at 0°, ≈ 1.22 at 19°", ETA_STUDY,
     _study_ratio("5", 0), ".2f", 1),
    ("docs/verification.md", "5 mm: 1.04 at 0°, ≈ {} at 19°", ETA_STUDY,
     _study_ratio("5", 19), ".2f", 1),
    ("docs/verification.md", "22° not measured (the rigid twin failed at {} s)", ETA_STUDY,
     _study("0", 22, "t_final"), ".3f", 1),
    ("docs/verification.md", "rectangle / trapezoid: no-slip +{} / +20.2 %", BED_MODELS,
     _against_paper_model("rectangle-glass-beads-no-slip-eta0.01"), ".1f", 100),
    ("docs/verification.md", "no-slip +12.8 / +{} %, material", BED_MODELS,
     _against_paper_model("trapezoid-glass-beads-no-slip-eta0.01"), ".1f", 100),
    ("docs/verification.md", "material +{} / +27.0 % |", BED_MODELS,
     _against_paper_model("rectangle-glass-beads-material-eta0.01"), ".1f", 100),
    ("docs/verification.md", "material +24.0 / +{} % |", BED_MODELS,
     _against_paper_model("trapezoid-glass-beads-material-eta0.01"), ".1f", 100),
    ("docs/erosion.md", "+11 to +{} mm at every slope run", ETA_STUDY,
     _study_gain("5", 19, "0.3"), ".0f", 1000),
    ("docs/erosion.md", "at 0, 19 and 22°); 93–{} % of it started beyond", ETA_STUDY,
     lambda d: 1 - d[f"{ETA_VARIANT}-5mm-19"]["displaced_from_under_column_share"], ".0f", 100),
    ("docs/erosion.md", "at 0, 19 and 22°); {}–98 % of it started beyond", ETA_STUDY,
     lambda d: 1 - d[f"{ETA_VARIANT}-5mm-22"]["displaced_from_under_column_share"], ".0f", 100),
    ("docs/erosion.md", "collapses 13 to {} % too far", BED_MODELS,
     _against_paper_model("trapezoid-glass-beads-no-slip-eta0.01"), ".0f", 100),
    ("docs/erosion.md", "every run came to rest within {} s", BED_MODELS,
     _flat("trapezoid-glass-beads-material-eta0.01", "stop_time_s"), ".2f", 1),
    ("docs/erosion.md", "(rectangle {} m, trapezoid 0.6647 m)", BED_MODELS,
     _flat("rectangle-drucker-prager-coulomb", "runout_m"), ".4f", 1),
    ("docs/erosion.md", "(rectangle 0.4252 m, trapezoid {} m)", BED_MODELS,
     _flat("trapezoid-drucker-prager-coulomb", "runout_m"), ".4f", 1),
    # --- the level collapses with eta = 0.01 (bed_models.py --viscosity 0.01)
    ("docs/erosion.md", "| no-slip | {} m, +12.8 %", BED_MODELS,
     _flat("rectangle-glass-beads-no-slip-eta0.01", "runout_m"), ".4f", 1),
    ("docs/erosion.md", "0.4797 m, +{} %, at rest at 0.896 s", BED_MODELS,
     _against_paper_model("rectangle-glass-beads-no-slip-eta0.01"), ".1f", 100),
    ("docs/erosion.md", "+12.8 %, at rest at {} s", BED_MODELS,
     _flat("rectangle-glass-beads-no-slip-eta0.01", "stop_time_s"), ".3f", 1),
    ("docs/erosion.md", "0.896 s | {} m, +20.2 %", BED_MODELS,
     _flat("trapezoid-glass-beads-no-slip-eta0.01", "runout_m"), ".4f", 1),
    ("docs/erosion.md", "0.7989 m, +{} %, at rest at 1.093 s", BED_MODELS,
     _against_paper_model("trapezoid-glass-beads-no-slip-eta0.01"), ".1f", 100),
    ("docs/erosion.md", "+20.2 %, at rest at {} s", BED_MODELS,
     _flat("trapezoid-glass-beads-no-slip-eta0.01", "stop_time_s"), ".3f", 1),
    ("docs/erosion.md", "| material | {} m, +24.0 %", BED_MODELS,
     _flat("rectangle-glass-beads-material-eta0.01", "runout_m"), ".4f", 1),
    ("docs/erosion.md", "0.5271 m, +{} %, at rest at 0.923 s", BED_MODELS,
     _against_paper_model("rectangle-glass-beads-material-eta0.01"), ".1f", 100),
    ("docs/erosion.md", "+24.0 %, at rest at {} s", BED_MODELS,
     _flat("rectangle-glass-beads-material-eta0.01", "stop_time_s"), ".3f", 1),
    ("docs/erosion.md", "0.923 s | {} m, +27.0 %", BED_MODELS,
     _flat("trapezoid-glass-beads-material-eta0.01", "runout_m"), ".4f", 1),
    ("docs/erosion.md", "0.8439 m, +{} %, at rest at 1.119 s", BED_MODELS,
     _against_paper_model("trapezoid-glass-beads-material-eta0.01"), ".1f", 100),
    ("docs/erosion.md", "+27.0 %, at rest at {} s", BED_MODELS,
     _flat("trapezoid-glass-beads-material-eta0.01", "stop_time_s"), ".3f", 1),
    # --- the slopes in the 10 cm channel (erosion_slopes.py, variant ...-walls)
    ("docs/erosion.md", "| rigid bed | {} m, at rest at 1.043 s |", WALLS_STUDY,
     _walls("0", 0, "runout_m"), ".4f", 1),
    ("docs/erosion.md", "| rigid bed | 0.4526 m, at rest at {} s |", WALLS_STUDY,
     _walls("0", 0, "stop_time_s"), ".3f", 1),
    ("docs/erosion.md", "| front {} m at 3 s, still creeping |", WALLS_STUDY,
     _walls("0", 19, "runout_m"), ".3f", 1),
    ("docs/erosion.md", "| 5 mm layer | {} m, at rest at 0.984 s", WALLS_STUDY,
     _walls("5", 0, "runout_m"), ".4f", 1),
    ("docs/erosion.md", "0.4741 m, at rest at {} s: ratio 1.05", WALLS_STUDY,
     _walls("5", 0, "stop_time_s"), ".3f", 1),
    ("docs/erosion.md", "at rest at 0.984 s: ratio {} |", WALLS_STUDY,
     _walls_ratio,
     ".2f", 1),
    ("docs/erosion.md", "the walls take {} % off the rigid", WALLS_STUDY,
     lambda d: 1 - d[f"{WALLS_VARIANT}-0mm-0"]["runout_m"]
     / NO_WALLS[f"{ETA_VARIANT}-0mm-0"]["runout_m"], ".1f", 100),
    ("docs/erosion.md", "runout ({} m without them)", ETA_STUDY,
     _study("0", 0, "runout_m"), ".4f", 1),
    ("docs/erosion.md", "the front is at {} m at 3 s, against", WALLS_STUDY,
     _walls("0", 19, "runout_m"), ".3f", 1),
    ("docs/erosion.md", "against {} m without walls; it moved", ETA_STUDY,
     _study("0", 19, "runout_m"), ".3f", 1),
    ("docs/erosion.md", "it moved {} mm in its last half second", WALLS_STUDY,
     lambda d: 1e3 * (d[f"{WALLS_VARIANT}-0mm-19"]["front_history"]["3"]
                      - d[f"{WALLS_VARIANT}-0mm-19"]["front_history"]["2.5"]), ".1f", 1),
    ("docs/erosion.md", "within the predicted 1.01–1.05** ({})", WALLS_STUDY,
     _walls_ratio,
     ".3f", 1),
    ("docs/erosion.md", "+{} mm at rest, against +20 mm without", WALLS_STUDY,
     _walls_gain(0, None), ".0f", 1),
    ("docs/erosion.md", "against +{} mm without walls. The walls shorten", WALLS_STUDY,
     _walls_gain(0, None, "none"), ".0f", 1),
    ("docs/erosion.md", "(+{} mm at 0.3 s, predicted +5", WALLS_STUDY,
     _walls_gain(0, "0.3"), ".0f", 1),
    ("docs/erosion.md", "At 19° the early gain (+{} mm at 0.3 s)", WALLS_STUDY,
     _walls_gain(19, "0.3"), ".0f", 1),
    ("docs/erosion.md", "and {}–99 % of it started beyond", WALLS_STUDY,
     _beyond_footprint(0), ".0f", 100),
    ("docs/erosion.md", "and 96–{} % of it started beyond", WALLS_STUDY,
     _beyond_footprint(19), ".0f", 100),
    ("docs/erosion.md", "The median advance is {} cm at 0°", WALLS_STUDY,
     _walls("5", 0, "displaced_advance_median_m"), ".1f", 100),
    ("docs/erosion.md", "and {} cm at 19°.", WALLS_STUDY,
     _walls("5", 19, "displaced_advance_median_m"), ".1f", 100),
    ("docs/erosion.md", "(+6.2 and +{} %), and over 5 mm", BED_MODELS,
     _against_paper_model("trapezoid-glass-beads-no-slip-eta0.01-walls0.1"), ".1f", 100),
    ("docs/verification.md", "no-slip +{} / +5.6 %, material +17.8", BED_MODELS,
     _against_paper_model("rectangle-glass-beads-no-slip-eta0.01-walls0.1"), ".1f", 100),
    ("docs/verification.md", "no-slip +6.2 / +{} %, material +17.8", BED_MODELS,
     _against_paper_model("trapezoid-glass-beads-no-slip-eta0.01-walls0.1"), ".1f", 100),
    ("docs/verification.md", "no-slip +6.2 / +5.6 %, material +{} / +12.2 %", BED_MODELS,
     _against_paper_model("rectangle-glass-beads-material-eta0.01-walls0.1"), ".1f", 100),
    ("docs/verification.md", "material +17.8 / +{} % | the no-slip bed passes", BED_MODELS,
     _against_paper_model("trapezoid-glass-beads-material-eta0.01-walls0.1"), ".1f", 100),
    ("docs/erosion.md", "| front {} m at 3 s, moving at 6 mm/s", WALLS_STUDY,
     _walls("5", 19, "runout_m"), ".3f", 1),
    ("docs/erosion.md", "m at 3 s, moving at {} mm/s: ratio", WALLS_STUDY,
     _walls("5", 19, "front_speed_end_m_s"), ".0f", 1000),
    ("docs/erosion.md", "moving at 6 mm/s: ratio ≈ {} |", WALLS_STUDY,
     _walls_ratio_at(19), ".2f", 1),
    ("docs/erosion.md", "The 19° ratio is as predicted** (≈ {}, in", WALLS_STUDY,
     _walls_ratio_at(19), ".3f", 1),
    ("docs/erosion.md", "still creeping | front {} m at 3 s, moving (run again", WALLS_STUDY,
     _walls("0", 22, "runout_m"), ".3f", 1),
    ("docs/erosion.md", "failed again**, at {} s (a boundary", WALLS_STUDY_316,
     _walls("0", 22, "t_final"), ".3f", 1),
    ("docs/erosion.md", "it reaches 3 s, its front\n   at {} m and still moving", WALLS_STUDY,
     _walls("0", 22, "runout_m"), ".3f", 1),
    ("docs/erosion.md", "Without walls it failed at {} s.", ETA_STUDY,
     _study("0", 22, "t_final"), ".3f", 1),
    ("docs/erosion.md", "its front is\n   within {} mm of the run without walls", WALLS_STUDY,
     lambda d: 1e3 * abs(d[f"{WALLS_VARIANT}-0mm-22"]["front_history"]["0.5"]
                         - NO_WALLS[f"{ETA_VARIANT}-0mm-22"]["front_history"]["0.5"]),
     ".0f", 1),
    ("docs/erosion.md", "At most {} % of it ends ahead of", WALLS_STUDY,
     _walls("5", 19, "displaced_ahead_of_column_share"), ".0f", 100),
    ("docs/erosion.md", "its ratio is 1.05 at 0° and ≈ {} at 19°", WALLS_STUDY,
     _walls_ratio_at(19), ".2f", 1),
    # --- the row at 22 degrees in the 10 cm channel
    ("docs/erosion.md", "the rigid twin's at {} m (106 mm/s)", WALLS_STUDY,
     _walls("0", 22, "runout_m"), ".3f", 1),
    ("docs/erosion.md", "at 1.721 m ({} mm/s)", WALLS_STUDY, _walls("0", 22, "front_speed_end_m_s"),
     ".0f", 1000),
    ("docs/erosion.md", "the layer at {} m (206 mm/s)", WALLS_STUDY, _walls("5", 22, "runout_m"),
     ".3f", 1),
    ("docs/erosion.md", "at 2.197 m ({} mm/s)", WALLS_STUDY, _walls("5", 22, "front_speed_end_m_s"),
     ".0f", 1000),
    ("docs/erosion.md", "**ratio ≈ {}**, a lower bound", WALLS_STUDY, _walls_ratio_at(22),
     ".2f", 1),
    ("docs/erosion.md", "≈ 1.15 and ≈ {} at 0, 10, 16, 19 and 22°", WALLS_STUDY,
     _walls_ratio_at(22), ".2f", 1),
    ("docs/erosion.md", "rigid twin's: +{}, +5, -18,", WALLS_STUDY, _walls_gain(22, "0.1"),
     ".0f", 1),
    ("docs/erosion.md", "rigid twin's: +11, +{}, -18,", WALLS_STUDY, _walls_gain(22, "0.3"),
     ".0f", 1),
    ("docs/erosion.md", "+11, +5, -{},\n  -96", WALLS_STUDY,
     lambda d: -_walls_gain(22, "0.5")(d), ".0f", 1),
    ("docs/erosion.md", "-18,\n  -{} and -110 mm", WALLS_STUDY,
     lambda d: -_walls_gain(22, "0.75")(d), ".0f", 1),
    ("docs/erosion.md", "-96 and -{} mm at 0.1, 0.3, 0.5, 0.75 and 1 s", WALLS_STUDY,
     lambda d: -_walls_gain(22, "1")(d), ".0f", 1),
    ("docs/erosion.md", "then +{}, +293, +407 and +476 mm", WALLS_STUDY, _walls_gain(22, "1.5"),
     ".0f", 1),
    ("docs/erosion.md", "then +97, +{}, +407 and +476 mm", WALLS_STUDY, _walls_gain(22, "2"),
     ".0f", 1),
    ("docs/erosion.md", "then +97, +293, +{} and +476 mm", WALLS_STUDY, _walls_gain(22, "2.5"),
     ".0f", 1),
    ("docs/erosion.md", "then +97, +293, +407 and +{} mm at 1.5,\n  2, 2.5 and 3 s", WALLS_STUDY,
     _walls_gain(22, "3"), ".0f", 1),
    ("docs/erosion.md", "displaced ({} cm² per centimetre", WALLS_STUDY,
     _walls("5", 22, "layer_displaced_area_m2"), ".1f", 1e4),
    ("docs/erosion.md", "width),\n  {} % of it ahead", WALLS_STUDY,
     _walls("5", 22, "displaced_ahead_of_column_share"), ".0f", 100),
    ("docs/erosion.md", "material, {} % from beyond the column's footprint,\n  median advance 10.3",
     WALLS_STUDY, lambda d: 1 - _walls("5", 22, "displaced_from_under_column_share")(d),
     ".0f", 100),
    ("docs/erosion.md", "median advance {} cm.\n- **With 22°", WALLS_STUDY,
     _walls("5", 22, "displaced_advance_median_m"), ".1f", 100),
    # --- the level row with four cells across the layer, in the 10 cm channel
    ("docs/erosion.md", "Four cells: {} m, at rest", WALLS_STUDY, _four("runout_m"), ".4f", 1),
    ("docs/erosion.md", "m, at rest\n  at {} s, ratio 1.051", WALLS_STUDY, _four("stop_time_s"),
     ".3f", 1),
    ("docs/erosion.md", "s, ratio {} (two cells:", WALLS_STUDY,
     lambda d: d[FOUR]["runout_m"] / d[f"{WALLS_VARIANT}-0mm-0"]["runout_m"], ".3f", 1),
    ("docs/erosion.md", "(two cells: {} m, 0.984 s, 1.048)", WALLS_STUDY,
     _walls("5", 0, "runout_m"), ".4f", 1),
    ("docs/erosion.md", "(two cells: 0.4741 m, {} s, 1.048)", WALLS_STUDY,
     _walls("5", 0, "stop_time_s"), ".3f", 1),
    ("docs/erosion.md", "(two cells: 0.4741 m, 0.984 s, {})", WALLS_STUDY, _walls_ratio,
     ".3f", 1),
    ("docs/erosion.md", "rigid twin's by +{} and +39 mm at 0.2", WALLS_STUDY, _four_gain("0.2"),
     ".0f", 1),
    ("docs/erosion.md", "by +24 and +{} mm at 0.2 and 0.3 s", WALLS_STUDY, _four_gain("0.3"),
     ".0f", 1),
    ("docs/erosion.md", "(two cells: +{} and\n  +36 mm)", WALLS_STUDY, _walls_gain(0, "0.2"),
     ".0f", 1),
    ("docs/erosion.md", "+22 and\n  +36 mm) and by +{} mm at rest", WALLS_STUDY,
     _four_gain(None), ".0f", 1),
    ("docs/erosion.md", "mm at rest (+{} mm).", WALLS_STUDY, _walls_gain(0, None), ".0f", 1),
    # --- the rows at 10 and 16 degrees in the 10 cm channel
    ("docs/erosion.md", "| rigid bed | {} m, at rest at 1.310 s (its front", WALLS_STUDY,
     _walls("0", 10, "runout_m"), ".4f", 1),
    ("docs/erosion.md", "| rigid bed | 0.6650 m, at rest at {} s (its front", WALLS_STUDY,
     _walls("0", 10, "stop_time_s"), ".3f", 1),
    ("docs/erosion.md", "at rest at 1.310 s (its front from {} s)", WALLS_STUDY,
     _walls("0", 10, "front_stop_time_s"), ".3f", 1),
    ("docs/erosion.md", "| front {} m at 2 s and at 3 s, the mass", WALLS_STUDY,
     lambda d: d[f"{WALLS_VARIANT}-0mm-16"]["front_history"]["2"], ".3f", 1),
    ("docs/erosion.md", "| front 0.942 m at 2 s and at 3 s, the mass", WALLS_STUDY,
     lambda d: d[f"{WALLS_VARIANT}-0mm-16"]["front_history"]["3"], ".3f", 1),
    ("docs/erosion.md", "the flowing area below 1 % from {} s)", WALLS_STUDY,
     _walls("0", 16, "duration_s"), ".3f", 1),
    ("docs/erosion.md", "| 5 mm layer | {} m, at rest at 1.258 s: ratio 1.04", WALLS_STUDY,
     _walls("5", 10, "runout_m"), ".4f", 1),
    ("docs/erosion.md", "| 5 mm layer | 0.6921 m, at rest at {} s: ratio 1.04", WALLS_STUDY,
     _walls("5", 10, "stop_time_s"), ".3f", 1),
    ("docs/erosion.md", "| 5 mm layer | 0.6921 m, at rest at 1.258 s: ratio {}", WALLS_STUDY,
     _walls_ratio_at(10), ".2f", 1),
    *_fronts_row("10°, walls", 10, ("0.1", "0.2", "0.3", "0.5", "0.75", "1", "-", None)),
    *_fronts_row("16°, walls", 16, ("0.1", "0.2", "0.3", "0.5", "0.75", "1", "1.5", None)),
    ("docs/erosion.md", "The ratio is {}, in the predicted 1.02–1.09", WALLS_STUDY,
     _walls_ratio_at(10), ".3f", 1),
    ("docs/erosion.md", "the layer\n  row runs +{} mm further", WALLS_STUDY,
     _walls_gain(10, None), ".0f", 1),
    ("docs/erosion.md", "It comes to rest {} s\n  before its twin", WALLS_STUDY,
     lambda d: d[f"{WALLS_VARIANT}-0mm-10"]["stop_time_s"]
     - d[f"{WALLS_VARIANT}-5mm-10"]["stop_time_s"], ".3f", 1),
    ("docs/erosion.md", "stay within {} mm of each other to 0.5 s", WALLS_STUDY,
     lambda d: max(abs(_walls_gain(10, t)(d)) for t in ("0.1", "0.2", "0.3", "0.5")),
     ".0f", 1),
    ("docs/erosion.md", "displaced ({} cm²\n  per centimetre", WALLS_STUDY,
     _walls("5", 10, "layer_displaced_area_m2"), ".1f", 1e4),
    ("docs/erosion.md", "width), {} % of it ends ahead of the column", WALLS_STUDY,
     _walls("5", 10, "displaced_ahead_of_column_share"), ".0f", 100),
    ("docs/erosion.md", "material, {} % of it\n  started beyond", WALLS_STUDY,
     _beyond_footprint(10), ".0f", 100),
    ("docs/erosion.md", "and its median advance is {} cm.", WALLS_STUDY,
     _walls("5", 10, "displaced_advance_median_m"), ".1f", 100),
    ("docs/erosion.md", "| {} m, at rest at 1.581 s: ratio ≈ 1.10", WALLS_STUDY,
     _walls("5", 16, "runout_m"), ".4f", 1),
    ("docs/erosion.md", "| 1.0352 m, at rest at {} s: ratio ≈ 1.10", WALLS_STUDY,
     _walls("5", 16, "stop_time_s"), ".3f", 1),
    ("docs/erosion.md", "| 1.0352 m, at rest at 1.581 s: ratio ≈ {} (the rigid", WALLS_STUDY,
     _walls_ratio_at(16), ".2f", 1),
    ("docs/erosion.md", "The layer row comes to rest at {} s at 1.0352 m", WALLS_STUDY,
     _walls("5", 16, "stop_time_s"), ".3f", 1),
    ("docs/erosion.md", "The layer row comes to rest at 1.581 s at {} m", WALLS_STUDY,
     _walls("5", 16, "runout_m"), ".4f", 1),
    ("docs/erosion.md", "twin's front stands at {} m from 2 s", WALLS_STUDY,
     lambda d: d[f"{WALLS_VARIANT}-0mm-16"]["front_history"]["2"], ".3f", 1),
    ("docs/erosion.md", "{} by the fronts, in the predicted 1.04–1.15", WALLS_STUDY,
     _walls_ratio_at(16), ".3f", 1),
    ("docs/erosion.md", "A small early gain (+{} mm at", WALLS_STUDY,
     _walls_gain(16, "0.1"), ".0f", 1),
    ("docs/erosion.md", "from 0.3 to 1.5 s (+{} mm)", WALLS_STUDY,
     _walls_gain(16, "1.5"), ".0f", 1),
    ("docs/erosion.md", "thin, and it falls to +{} mm as the rigid", WALLS_STUDY,
     _walls_gain(16, None), ".0f", 1),
    ("docs/erosion.md", "smaller than at 19° (+{} mm at 3 s)", WALLS_STUDY,
     _walls_gain(19, "3"), ".0f", 1),
    ("docs/erosion.md", "displaced ({} cm²),\n  0 % of it", WALLS_STUDY,
     _walls("5", 16, "layer_displaced_area_m2"), ".1f", 1e4),
    ("docs/erosion.md", "(41.3 cm²),\n  {} % of it ends ahead", WALLS_STUDY,
     _walls("5", 16, "displaced_ahead_of_column_share"), ".0f", 100),
    ("docs/erosion.md", "material, {} % of it started beyond the column's\n  footprint",
     WALLS_STUDY, _beyond_footprint(16), ".0f", 100),
    ("docs/erosion.md", "footprint, and its median advance is {} cm.", WALLS_STUDY,
     _walls("5", 16, "displaced_advance_median_m"), ".1f", 100),
    ("docs/erosion.md", "over 5 mm {}, 1.04, ≈ 1.10 and ≈ 1.15", WALLS_STUDY,
     _walls_ratio, ".2f", 1),
    ("docs/erosion.md", "over 5 mm 1.05, {}, ≈ 1.10 and ≈ 1.15", WALLS_STUDY,
     _walls_ratio_at(10), ".2f", 1),
    ("docs/erosion.md", "over 5 mm 1.05, 1.04, ≈ {} and ≈ 1.15", WALLS_STUDY,
     _walls_ratio_at(16), ".2f", 1),
    ("docs/erosion.md", "over 5 mm 1.05, 1.04, ≈ 1.10 and ≈ {}", WALLS_STUDY,
     _walls_ratio_at(19), ".2f", 1),
    ("docs/erosion.md", "(a +{} mm gain the experiments do not see), as", WALLS_STUDY,
     _walls_gain(10, None), ".0f", 1),
    # --- the level collapses with eta = 0.01 in the 10 cm channel (--channel-width 0.1)
    ("docs/erosion.md", "| no-slip | {} m, +6.2 %, at rest at 1.036 s", BED_MODELS,
     _flat("rectangle-glass-beads-no-slip-eta0.01-walls0.1", "runout_m"), ".4f", 1),
    ("docs/erosion.md", "0.4514 m, +{} %, at rest at 1.036 s", BED_MODELS,
     _against_paper_model("rectangle-glass-beads-no-slip-eta0.01-walls0.1"), ".1f", 100),
    ("docs/erosion.md", "+6.2 %, at rest at {} s", BED_MODELS,
     _flat("rectangle-glass-beads-no-slip-eta0.01-walls0.1", "stop_time_s"), ".3f", 1),
    ("docs/erosion.md", "1.036 s | {} m, +5.6 %", BED_MODELS,
     _flat("trapezoid-glass-beads-no-slip-eta0.01-walls0.1", "runout_m"), ".4f", 1),
    ("docs/erosion.md", "0.7018 m, +{} %, at rest at 1.841 s", BED_MODELS,
     _against_paper_model("trapezoid-glass-beads-no-slip-eta0.01-walls0.1"), ".1f", 100),
    ("docs/erosion.md", "+5.6 %, at rest at {} s", BED_MODELS,
     _flat("trapezoid-glass-beads-no-slip-eta0.01-walls0.1", "stop_time_s"), ".3f", 1),
    ("docs/erosion.md", "| material | {} m, +17.8 %", BED_MODELS,
     _flat("rectangle-glass-beads-material-eta0.01-walls0.1", "runout_m"), ".4f", 1),
    ("docs/erosion.md", "0.5009 m, +{} %, at rest at 1.002 s", BED_MODELS,
     _against_paper_model("rectangle-glass-beads-material-eta0.01-walls0.1"), ".1f", 100),
    ("docs/erosion.md", "+17.8 %, at rest at {} s", BED_MODELS,
     _flat("rectangle-glass-beads-material-eta0.01-walls0.1", "stop_time_s"), ".3f", 1),
    ("docs/erosion.md", "1.002 s | {} m, +12.2 %", BED_MODELS,
     _flat("trapezoid-glass-beads-material-eta0.01-walls0.1", "runout_m"), ".4f", 1),
    ("docs/erosion.md", "0.7458 m, +{} %, at rest at 1.480 s", BED_MODELS,
     _against_paper_model("trapezoid-glass-beads-material-eta0.01-walls0.1"), ".1f", 100),
    ("docs/erosion.md", "+12.2 %, at rest at {} s", BED_MODELS,
     _flat("trapezoid-glass-beads-material-eta0.01-walls0.1", "stop_time_s"), ".3f", 1),
    ("docs/erosion.md", "now {} and 6.2 mm from the paper model's", BED_MODELS,
     _flat("rectangle-glass-beads-no-slip-eta0.01-walls0.1", "surface_to_paper_model_mean_mm"),
     ".1f", 1),
    ("docs/erosion.md", "now 5.1 and {} mm from the paper model's", BED_MODELS,
     _flat("trapezoid-glass-beads-no-slip-eta0.01-walls0.1", "surface_to_paper_model_mean_mm"),
     ".1f", 1),
    ("docs/erosion.md", "against {} and 21.8 mm without walls", BED_MODELS,
     _flat("rectangle-glass-beads-no-slip-eta0.01", "surface_to_paper_model_mean_mm"),
     ".1f", 1),
    ("docs/erosion.md", "against 10.1 and {} mm without walls", BED_MODELS,
     _flat("trapezoid-glass-beads-no-slip-eta0.01", "surface_to_paper_model_mean_mm"),
     ".1f", 1),
    ("docs/erosion.md", "by {} % (rectangle) and", BED_MODELS,
     _spreading_cut("rectangle", 0.20), ".1f", 100),
    ("docs/erosion.md", "and {} % (trapezoid) on the no-slip bed", BED_MODELS,
     _spreading_cut("trapezoid", 0.297), ".1f", 100),
    ("docs/erosion.md", "Without walls it ran +{} % and +20.2 %", BED_MODELS,
     _against_paper_model("rectangle-glass-beads-no-slip-eta0.01"), ".1f", 100),
    ("docs/erosion.md", "Without walls it ran +12.8 % and +{} %", BED_MODELS,
     _against_paper_model("trapezoid-glass-beads-no-slip-eta0.01"), ".1f", 100),
    ("docs/erosion.md", "the paper's model they cut it by {} % and", "side_walls/side_walls.json",
     _walls_cut("rectangle-rigid", 0.20), ".1f", 100),
    ("docs/erosion.md", "% and {} % ([side walls]", "side_walls/side_walls.json",
     _walls_cut("trapezoid-rigid", 0.297), ".1f", 100),
    ("docs/erosion.md", "(the no-slip trapezoid's at {} s, against", BED_MODELS,
     _flat("trapezoid-glass-beads-no-slip-eta0.01-walls0.1", "front_stop_time_s"), ".3f", 1),
    ("docs/erosion.md", "s, against {} s without)", BED_MODELS,
     _flat("trapezoid-glass-beads-no-slip-eta0.01", "front_stop_time_s"), ".3f", 1),
    ("docs/erosion.md", "comes to rest {} s later than without walls", BED_MODELS,
     lambda d: (d["flat"]["trapezoid-glass-beads-no-slip-eta0.01-walls0.1"]["stop_time_s"]
                - d["flat"]["trapezoid-glass-beads-no-slip-eta0.01"]["stop_time_s"]),
     ".2f", 1),
]


def _claims_of(name: str) -> list[tuple]:
    """The CLAIMS of the sibling module ``name``.py (the erosion studies' claims)."""
    spec = importlib.util.spec_from_file_location(name, Path(__file__).with_name(f"{name}.py"))
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module.CLAIMS


# the side-walls study carried to rest, the thickness at 19 degrees, the level gain's checks
CLAIMS += _claims_of("claims_erosion_walls")
# the sliding beds, the paper's model on two meshes, the rigid twins' fronts at 1 mm
CLAIMS += _claims_of("claims_erosion_beds")


def lookup(data: Any, path: Path_) -> Any:
    """The value at ``path``: keys and list filters separated by dots (``A.stop_time_s``,
    ``results[eps!=0.01].ratio``, ``[case=mu-i 23 deg&cells=32].error_exact``), with
    ``min:`` or ``max:`` over the values a filter leaves; or a function of the data."""
    if callable(path):
        return path(data)
    reduce, _, path = path.rpartition(":") if path[:4] in ("min:", "max:") else ("", "", path)
    values = [data]
    for part in re.findall(r"\[[^\]]*\]|[^.\[]+", path):
        if part.startswith("["):
            values = [item for v in values for item in v if _matches(item, part[1:-1])]
        else:
            values = [v[part] if isinstance(v, dict) else item[part]
                      for v in values for item in ([v] if isinstance(v, dict) else v)]
    if reduce:
        return {"min": min, "max": max}[reduce](values)
    assert len(values) == 1, f"{path} selects {len(values)} values"
    return values[0]


def _matches(item: dict[str, Any], conditions: str) -> bool:
    for condition in conditions.split("&"):
        key, op, wanted = re.match(r"([^!=]+)(!?=)(.*)", condition).groups()  # type: ignore[union-attr]
        value = item.get(key)
        try:
            equal = math.isclose(float(value), float(wanted))
        except (TypeError, ValueError):
            equal = str(value) == wanted
        if equal != (op == "="):
            return False
    return True


def formatted(value: float, spec: str, scale: float) -> str:
    """``value * scale`` as the pages write it: 2.1e-5 (no exponent padding), 3,578."""
    if spec == ",d":
        return f"{round(value * scale):,d}"
    text = format(value * scale, spec)
    return re.sub(r"e([+-])0*(\d)", lambda m: f"e{'-' if m[1] == '-' else ''}{m[2]}", text)


def words(text: str) -> str:
    return re.sub(r"\s+", " ", text)


@pytest.mark.parametrize("page, text, results, path, spec, scale", CLAIMS,
                         ids=[f"{c[0]}:{c[1][:40]}" for c in CLAIMS])
def test_a_documented_number_is_its_results_files(page: str, text: str, results: str,
                                                  path: Path_, spec: str,
                                                  scale: float) -> None:
    value = lookup(json.loads((RESULTS / results).read_text()), path)
    quoted = words(text.format(formatted(value, spec, scale)))
    assert quoted in words((ROOT / page).read_text(encoding="utf-8")), (
        f"{page} should say '{quoted}' ({results}: {path})")


def test_each_example_shows_its_figure() -> None:
    page = (ROOT / "docs" / "examples.md").read_text(encoding="utf-8")
    for script in sorted((ROOT / "examples").glob("*.py")):
        figure = f"img/examples/{script.stem}.png"
        assert f"examples/{script.name}" in page and figure in page, script.name
        assert (ROOT / "docs" / figure).is_file(), figure


@pytest.mark.parametrize("state", ["rest", "flowing", "front"])
def test_the_fieldsplit_table_is_its_results_files(state: str) -> None:
    """docs/three_d.md's table of PETSc's fieldsplit steps, row by row."""
    cells = []
    for variant, sizes in SPLIT_SIZES.items():
        steps = [next(r["steps"] for r in json.loads(
            (RESULTS / f"three_d_krylov/fieldsplit_{state}_h{size}.json").read_text())
            if r["variant"] == variant) for size in sizes]
        cells.append(" / ".join(map(str, steps)))
    row = f"| {state} | " + " | ".join(cells) + " |"
    assert row in (ROOT / "docs" / "three_d.md").read_text(encoding="utf-8"), row


RIGID_ROWS = {"left-preconditioned GMRes": "ranks", "FGMRes unscaled": "ranks_flexible"}
RIGID_SIZES = {"973": "0.04", "5,414": "0.02"}


def _rigid_cell(kind: str, state: str, size: str) -> str:
    """One cell of the rigid-body modes' table: steps without / with the modes ("fails
    (400)" where a solve did not converge)."""
    cells = []
    for name in (kind, f"{kind}_rigid"):
        record = json.loads((RESULTS / f"three_d_krylov/fieldsplit_{name}_{state}_h{size}_n1"
                                       ".json").read_text())
        cells.append(str(record["steps"]) if record["converged"]
                     else f"fails ({record['steps']})")
    return " / ".join(cells)


@pytest.mark.parametrize("row", [f"{v}, {n}" for v in RIGID_ROWS for n in RIGID_SIZES])
def test_the_rigid_modes_table_is_its_results_files(row: str) -> None:
    """docs/three_d.md's table of the fieldsplit steps without and with the rigid modes."""
    variant, unknowns = row.split(", ")
    size = RIGID_SIZES[unknowns]
    cells = [_rigid_cell(RIGID_ROWS[variant], state, size)
             for state in ("rest", "flowing", "front")]
    line = f"| {row} | " + " | ".join(cells) + " |"
    assert line in (ROOT / "docs" / "three_d.md").read_text(encoding="utf-8"), line


@pytest.mark.parametrize("state", ["rest", "flowing", "front"])
@pytest.mark.parametrize("size", ["0.04", "0.02"])
def test_the_scaled_fieldsplit_takes_one_process_steps_on_two_ranks(state: str,
                                                                   size: str) -> None:
    """docs/three_d.md: the scaled selfp's steps on two ranks are one process's."""
    one, two = (json.loads((RESULTS / "three_d_fieldsplit" / (
        f"fieldsplit_ranks_flexible_rigid_scaled_{state}_h{size}_n{n}.json")).read_text())
        for n in (1, 2))
    assert two["converged"] and two["steps"] == one["steps"]


def test_the_scaled_fieldsplit_table_is_its_results_files() -> None:
    """docs/three_d.md's table of the FGMRes variants, scaled and not: the table
    benchmarks/three_d_fieldsplit.py --table draws from the records, row by row."""
    import sys

    sys.path.insert(0, str(ROOT / "benchmarks"))
    from common.fieldsplit_table import table

    drawn = table(RESULTS / "three_d_fieldsplit")
    assert drawn == json.loads((RESULTS / SCALED_TABLE).read_text())["table"]
    page = (ROOT / "docs" / "three_d.md").read_text(encoding="utf-8")
    for row in drawn.splitlines()[2:]:
        assert row in page, row


TIMING_KINDS = {"`selfp`": "flexible_rigid_scaled",
                "Cahouet-Chabard": "cahouet-chabard_rigid_scaled",
                "LSC": "lsc-gamg-flexible_rigid_scaled"}


@pytest.mark.parametrize("name", list(TIMING_KINDS))
def test_the_fieldsplit_timing_table_is_its_results_files(name: str) -> None:
    """docs/three_d.md's processor seconds of one solve at 18,192 unknowns, by variant."""
    cells = []
    for state in ("rest", "flowing", "front"):
        record = json.loads((RESULTS / "three_d_fieldsplit/timing" / (
            f"fieldsplit_ranks_{TIMING_KINDS[name]}_{state}_h0.014_n1.json")).read_text())
        cpu = record["cpu_s_per_rank"][0]
        cells.append(f"{cpu['solve']:.1f} ({cpu['direct']:.1f})")
    line = f"| {name} | " + " | ".join(cells) + " |"
    assert line in (ROOT / "docs" / "three_d.md").read_text(encoding="utf-8"), line


COLLAPSE_ROWS = {"1, PARDISO": "n1_t0.03", "1, fieldsplit": "n1_fieldsplit_t0.03",
                 "2, `masterinverse`": "n2_t0.03", "2, fieldsplit": "n2_fieldsplit_t0.03"}


def _collapse(name: str) -> Any:
    return json.loads((RESULTS / f"three_d_collapse/rest_h0.04_{name}.json").read_text())


@pytest.mark.parametrize("row", list(COLLAPSE_ROWS))
def test_the_fieldsplit_collapse_table_is_its_results_files(row: str) -> None:
    """docs/three_d.md's table of the coarse collapse to 0.03 s, direct and fieldsplit."""
    path = RESULTS / f"three_d_collapse/rest_h0.04_{COLLAPSE_ROWS[row]}.json"
    if not path.exists():
        pytest.skip(f"{path.name} not recorded")
    d = _collapse(COLLAPSE_ROWS[row])
    load = d["load_average"]
    line = (f"| {row} | {d['steps']} | {d['nonlinear_iterations']} | "
            f"{d['runout_centre_m']:.6f} / {d['runout_wall_m']:.6f} | {d['cpu_s']:.1f} | "
            f"{load[0]:.1f}, {load[3]:.1f} |")
    assert line in (ROOT / "docs" / "three_d.md").read_text(encoding="utf-8"), line


SCALED_COLLAPSE_ROWS = {"1, PARDISO": "n1_t0.03", "1, fieldsplit": "n1_fieldsplit_t0.03",
                        "2, `masterinverse`": "n2_t0.03", "2, fieldsplit": "n2_fieldsplit_t0.03"}


@pytest.mark.parametrize("row", list(SCALED_COLLAPSE_ROWS))
def test_the_scaled_fieldsplit_collapse_table_is_its_results_files(row: str) -> None:
    """docs/three_d.md's table of the coarse collapse to 0.03 s with the scaled solve."""
    path = RESULTS / f"three_d_fieldsplit/rest_h0.04_{SCALED_COLLAPSE_ROWS[row]}.json"
    if not path.exists():
        pytest.skip(f"{path.name} not recorded")
    d = _scaled_collapse(SCALED_COLLAPSE_ROWS[row])
    load = d["load_average"]
    krylov = (f"{d['krylov_iterations']} ({d['krylov_largest']})"
              if d.get("krylov_iterations") is not None else "-")
    line = (f"| {row} | {d['steps']} | {d['nonlinear_iterations']} | "
            f"{d['runout_centre_m']:.6f} / {d['runout_wall_m']:.6f} | {krylov} | "
            f"{d['cpu_s']:.1f} | {load[0]:.1f}, {load[3]:.1f} |")
    assert line in (ROOT / "docs" / "three_d.md").read_text(encoding="utf-8"), line


def test_the_cost_growth_tables_are_their_results_files() -> None:
    """docs/three_d.md's cost-growth tables: what three_d_fieldsplit_cost.py --table draws
    from the records (cost.md), row by row."""
    import sys

    sys.path.insert(0, str(ROOT / "benchmarks"))
    from common.fieldsplit_cost import report

    drawn, data = report(RESULTS / "three_d_fieldsplit")
    assert drawn + "\n" == (RESULTS / "three_d_fieldsplit/cost.md").read_text()
    assert data == json.loads((RESULTS / COST).read_text())
    page = (ROOT / "docs" / "three_d.md").read_text(encoding="utf-8")
    rows = [r for r in drawn.splitlines() if r.startswith("| ") and "---" not in r]
    assert len(rows) > 20
    for row in rows:
        assert row in page, row


@pytest.mark.parametrize("state", ["rest", "flowing", "front"])
@pytest.mark.parametrize("size", ["0.04", "0.02"])
def test_lsc_on_two_ranks_takes_one_process_steps_within_one(state: str, size: str) -> None:
    """docs/three_d.md: LSC, the setting's solve, on two ranks converges within one step of
    one process's steps."""
    one, two = (json.loads((RESULTS / "three_d_fieldsplit" / (
        f"fieldsplit_ranks_lsc-gamg-flexible_rigid_scaled_{state}_h{size}_n{n}.json")
        ).read_text()) for n in (1, 2))
    assert two["converged"] and abs(two["steps"] - one["steps"]) <= 1

@pytest.mark.parametrize("ranks", [1, 2])
def test_the_lsc_collapse_row_is_its_results_file(ranks: int) -> None:
    """docs/three_d.md's coarse collapse to 0.03 s with LSC, the setting's solve."""
    d = json.loads((RESULTS / (COST_LSC if ranks == 1 else COST_LSC_2)).read_text())
    load = d["load_average"]
    line = (f"| {ranks}, fieldsplit (LSC) | {d['steps']} | {d['nonlinear_iterations']} | "
            f"{d['runout_centre_m']:.6f} / {d['runout_wall_m']:.6f} | "
            f"{d['krylov_iterations']} ({d['krylov_largest']}) | "
            f"{d['cpu_s']:.1f} | {load[0]:.1f}, {load[3]:.1f} |")
    assert line in (ROOT / "docs" / "three_d.md").read_text(encoding="utf-8"), line
    direct = _scaled_collapse(f"n{ranks}_t0.03")
    assert (d["steps"], d["nonlinear_iterations"]) == (direct["steps"],
                                                       direct["nonlinear_iterations"])


def _fronts_apart(key: str, ranks: int) -> Callable[[Any], float]:
    """|fieldsplit - direct| of a front at 0.03 s (m), on ``ranks`` ranks."""
    direct = _collapse(f"n{ranks}_t0.03")
    return lambda d: abs(d[key] - direct[key])


# what a run's record measures of the machine rather than of the run
MACHINE = ("cpu_s", "wall_s", "load_average", "peak_mb", "profile")


@pytest.mark.parametrize("record, before", [(CHANNEL, CHANNEL_7A), (SLOPE19, SLOPE19_OLD),
                                            (REST_1, REST_1_323)])
def test_a_3d_rerun_repeats_its_record_to_the_digit(record: str, before: str) -> None:
    """docs/three_d.md: the runs made again after the lofted faces' labels were corrected
    are the records made before it in every figure but the machine's (processor and wall
    time, load, memory, profile)."""
    new, old = (json.loads((RESULTS / name).read_text()) for name in (record, before))
    for data in (new, old):
        for figures in (data, *data.get("runs", {}).values()):
            for key in MACHINE:
                figures.pop(key, None)
    assert new == old
