"""The erosion-on-slopes study's variants: each a set of overrides applied to a row's rigid
and erodible runs alike (``benchmarks/erosion_slopes.py``), with where their rigid twin and
their layer's length differ from the study's rule."""

from __future__ import annotations

GLASS_BEADS = ["material.rheology=mu-i", "material.friction_angle_deg=20.9",
               "material.mu_2_deg=32.76", "material.i0=0.279",
               "material.grain_diameter=0.00053"]
# mu_start at the avalanche angle; tau_m = tau_r = 0.02 s (about 3 sqrt(d/g)) and the
# threshold 1 1/s (benchmarks/hysteresis.py) are the option's defaults
HYSTERETIC = [*GLASS_BEADS, "material.friction=hysteretic",
              "material.start_friction_angle_deg=25.5"]
# the candidate's bed and channel: no-slip, eta / 100, the experiments' 10 cm side walls
CHANNEL = ["boundary.bed=no-slip", "material.viscosity=0.01", "boundary.channel_width=0.1"]
TALLER = "geometry.height=0.145"   # the rectangle's 14 cm and a 5 mm layer's material under it
FINE = "mesh.size=0.007"           # half the scenario's cells' size
FINER = "mesh.size=0.0035"         # a quarter: the third mesh of the rigid runout's convergence
TENSION = ["surface_tension.enabled=true", "surface_tension.length=mesh_size"]   # the layer rows'


def sliding(bed: str, *extra: str) -> list[str]:
    """The candidate's set-up (the beads, eta / 100, the walls) on a bed that slides."""
    return [*GLASS_BEADS, f"boundary.bed={bed}", *CHANNEL[1:], *extra]


VARIANTS = {
    # the paper's constants: internal and bed friction 25.5 deg (the beads' avalanche
    # angle), eta = 1 Pa s
    "drucker-prager": [],
    "mu-i": ["material.rheology=mu-i"],                  # Jop et al. (2006) glass beads
    "small-eta": ["material.viscosity=0.01"],            # eta / 100
    "stop-angle": ["material.friction_angle_deg=23.5",   # friction at the repose angle
                   "boundary.bed_friction_deg=23.5"],
    "loose-layer": ["layer.density=1450", "layer.friction_angle_deg=23.5"],  # packing 0.58
    "side-walls": ["boundary.channel_width=0.1"],        # the experiments' 10 cm channel
    # column and layer of the glass beads of Jop, Forterre & Pouliquen (2005, J. Fluid Mech.
    # 541, d = 0.53 mm; 2006, Nature 441): mu(I) from tan 20.9 to tan 32.76 deg, I0 = 0.279;
    # the rigid bed's Coulomb friction kept at 25.5 deg
    "glass-beads": GLASS_BEADS,
    # the same beads flowing, starting at their avalanche angle (the study's docstring)
    "hysteretic": HYSTERETIC,
    # the chosen parameters of the hysteretic law, each by a factor of two (the start
    # angle by 2 deg), for one slope and layer
    "hysteretic-tau-x2": [*HYSTERETIC, "material.mobilisation_time=0.04",
                          "material.rest_time=0.04"],
    "hysteretic-tau-half": [*HYSTERETIC, "material.mobilisation_time=0.01",
                            "material.rest_time=0.01"],
    "hysteretic-rate-x2": [*HYSTERETIC, "material.mobilisation_shear_rate=2.0"],
    "hysteretic-rate-half": [*HYSTERETIC, "material.mobilisation_shear_rate=0.5"],
    "hysteretic-start-27.5": [*HYSTERETIC[:-1], "material.start_friction_angle_deg=27.5"],
    "hysteretic-start-23.5": [*HYSTERETIC[:-1], "material.start_friction_angle_deg=23.5"],
    # the regularising viscosity eta / 100 (column and layer): what the sheared layer's
    # viscous share does to the ratio (benchmarks/erosion_slopes_stress.py)
    "hysteretic-small-eta": [*HYSTERETIC, "material.viscosity=0.01"],
    # the nonlocal fluidity law with the glass beads' constants of Henann & Kamrin (2013):
    # mu_s = tan 20.9, b = 0.9377, A = 0.48 (the law's defaults), d = 0.53 mm
    "nonlocal": ["material.rheology=nonlocal", "material.friction_angle_deg=20.9",
                 "material.grain_diameter=0.00053"],
    # the glass beads' mu(I) with eta / 100 (column and layer) on a rigid bed that does
    # not slide, or whose friction is the beads' own at the slip's rate (boundary.bed):
    # the slab test's pair (benchmarks/slab.py) on the collapse
    "glass-beads-no-slip-small-eta": [*GLASS_BEADS, "boundary.bed=no-slip",
                                      "material.viscosity=0.01"],
    "glass-beads-material-small-eta": [*GLASS_BEADS, "boundary.bed=material",
                                       "material.viscosity=0.01"],
    # the same on the no-slip bed in the experiments' 10 cm channel: the side walls'
    # depth-averaged drag (2 mu_w / W) p, mu_w = tan 10.2 deg
    "glass-beads-no-slip-small-eta-walls": [*GLASS_BEADS, *CHANNEL],
    # the paper's rate-independent law (Drucker-Prager, 25.5 deg) in the same channel on
    # the same no-slip bed with eta / 100: the control that says whether the candidate's
    # gain on the level bed needs the beads' rate dependence
    "drucker-prager-no-slip-small-eta-walls": CHANNEL,
    # rigid rows only: the column 14.5 cm high, as much material at the gate as a column
    # standing on a 5 mm layer (the layer under its footprint): that share of a layer
    # row's gain on the level bed; 15 cm, as on a 10 mm layer
    "glass-beads-no-slip-small-eta-walls-taller": [*GLASS_BEADS, *CHANNEL, TALLER],
    "drucker-prager-no-slip-small-eta-walls-taller": [*CHANNEL, TALLER],
    "glass-beads-no-slip-small-eta-walls-15cm": [*GLASS_BEADS, *CHANNEL, "geometry.height=0.15"],
    # the 14 and 14.5 cm rigid columns on a mesh twice as fine: how much of their
    # difference is the mesh's; then the candidate's rows again on that mesh
    "glass-beads-no-slip-small-eta-walls-fine": [*GLASS_BEADS, *CHANNEL, FINE],
    "glass-beads-no-slip-small-eta-walls-taller-fine": [*GLASS_BEADS, *CHANNEL, TALLER, FINE],
    # the rigid row on a mesh four times as fine: the rigid runout's order of convergence
    "glass-beads-no-slip-small-eta-walls-finer": [*GLASS_BEADS, *CHANNEL, FINER],
    # rigid rows on the finer mesh with the layer rows' numerical surface tension at the
    # front (3.8)-(3.11): the 19-degree rigid twin's surface folded at 0.596 s without it
    "glass-beads-no-slip-small-eta-walls-fine-tension": [*GLASS_BEADS, *CHANNEL, FINE, *TENSION],
    # and on the study's mesh: what the twins' different front treatment did to its ratios
    "glass-beads-no-slip-small-eta-walls-tension": [*GLASS_BEADS, *CHANNEL, *TENSION],
    # and a quarter of the study's cells: the third mesh with the tension
    "glass-beads-no-slip-small-eta-walls-finer-tension": [*GLASS_BEADS, *CHANNEL, FINER,
                                                          *TENSION],
    # the rough bed's candidates that slide, the study's set-up otherwise (the beads, eta /
    # 100, the 10 cm channel), level rigid rows on three meshes: which bed's rigid runout
    # has a mesh limit, and which limit is the paper's model's (whose own three meshes are
    # drucker-prager, -fine, -finer): the Coulomb bed at 25.5 deg, the beads' own law
    **{f"glass-beads-{bed}-small-eta-walls{mesh}": sliding(bed, *extra)
       for bed in ("coulomb", "material")
       for mesh, extra in (("", []), ("-fine", [FINE]), ("-finer", [FINER]))},
    # the sliding beds' rigid twins with the layer rows' front treatment
    "glass-beads-material-small-eta-walls-tension": sliding("material", *TENSION),
    "glass-beads-coulomb-small-eta-walls-tension": sliding("coulomb", *TENSION),
    "glass-beads-material-small-eta-walls-fine-tension": sliding("material", FINE, *TENSION),
    "drucker-prager-fine": [FINE],
    "drucker-prager-finer": [FINER],
}
RIGID_TWIN = {"loose-layer": "drucker-prager"}   # only the layer differs: same rigid bed
# how far the layer reaches, in rigid runouts: further where the layer may lengthen the
# runout by more than 30 % (the meshed layer ends mesh.layer_ahead ahead of the flow, so
# an unused length costs nothing)
REACH = {"glass-beads-no-slip-small-eta": 2.0, "glass-beads-material-small-eta": 2.0}
# a layer of a fixed length (m), so that it need not wait for its rigid twin: 3 m is twice
# the furthest front of the rows without walls at 0-19 degrees (1.46 m at 3 s)
LENGTH = {"glass-beads-no-slip-small-eta-walls": 3.0,
          "drucker-prager-no-slip-small-eta-walls": 3.0,
          "glass-beads-material-small-eta-walls": 3.0,
          "glass-beads-material-small-eta-walls-fine": 3.0,
          "glass-beads-coulomb-small-eta-walls": 3.0}
