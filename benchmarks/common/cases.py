"""Cases several benchmarks share: the paper's algorithm as overrides (A in speed.py and
primal_dual.py), the speed cases, and the section 5.2 set-up of rheologies.py and
mu_i_refinement.py."""

from __future__ import annotations

# --- the paper's algorithm (A) and the speed cases (speed.py, primal_dual.py) ----------
PAPER = ["numerics.linearization=picard", "time.adaptive=false", "time.dt_init=1e-8",
         "time.dt_growth=1.1", "time.dt_max=1e-4", "numerics.tol=1e-4",
         "numerics.tol_init=1e-6", "numerics.ale_extrapolation=false",
         "numerics.initial_guess=previous",
         "time.stop_at_rest=false"]
PAPER_TO_REST = [o for o in PAPER if not o.startswith("time.stop_at_rest")]
# the first verified runs: the paper's algorithm without quality remeshing, with UMFPACK
TODAY = ["mesh.remesh_quality=0", "numerics.linear_solver=umfpack"]
PLUG_PAPER = ["numerics.linearization=picard"]           # the plug flow's fixed dt and tol
CASES: dict[str, tuple[str, list[str], list[str]]] = {
    # name: (scenario, overrides of both, overrides of A only)
    "trapezoid": ("trapezoid-rigid", [], PAPER),
    "rectangle": ("rectangle-rigid", [], PAPER),
    "erodible": ("trapezoid-erodible", [], PAPER),     # A takes hours: run it on its own
    "plug-flow": ("plug-flow", ["numerics.eps=1e-6", "mesh.size=0.125", "time.t_end=0.2"],
                  PLUG_PAPER),
    # the column that stalled the fixed-point iteration near rest, and rectangles of
    # l0 = 10 cm, h0/l0 = 0.5, 1, 2, both algorithms to rest
    "stall": ("rectangle-rigid", ["geometry.width=0.1", "geometry.height=0.05",
                                  "time.t_end=2", "time.output_times=[0.1,0.2,0.3]"],
              PAPER_TO_REST),
    "square": ("rectangle-rigid", ["geometry.width=0.1", "geometry.height=0.1",
                                   "time.t_end=2", "time.output_times=[0.1,0.2,0.3,0.5]"],
               PAPER_TO_REST),
    "tall": ("rectangle-rigid", ["geometry.width=0.1", "geometry.height=0.2",
                                 "time.t_end=2", "time.output_times=[0.1,0.2,0.3,0.5]"],
             PAPER_TO_REST),
}

# --- the section 5.2 set-up (rheologies.py, mu_i_refinement.py) -------------------------
SETUP = ["time.adaptive=false", "time.dt=1e-3", "numerics.tol=1e-3", "time.t_end=2.0",
         "time.stop_at_rest=true"]
SCENARIO = {"trapezoid": "trapezoid-rigid", "rectangle": "rectangle-rigid",
            "trapezoid-erodible": "trapezoid-erodible"}
