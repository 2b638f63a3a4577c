"""The problem kinds and the built-in scenarios (TOML package data).

A built-in kind is one line of ``BUILT_IN``: the module that declares it to the
configuration (its ``KindRules``, engine-free, imported with the package so that every
configuration is checked by its kind's rules) and the module of its builder (imported when
a problem is built, ``registry.py``).
"""

import importlib

from granflow.config.scenario_files import builtin_scenarios, scenario_text

BUILT_IN = (("granflow.scenarios.column_rules", "granflow.scenarios.column"),
            ("granflow.scenarios.plug_flow_rules", "granflow.scenarios.plug_flow"),
            ("granflow.scenarios.slab_rules", "granflow.scenarios.slab"),
            # three dimensions (geometry.dimension = 3): the same kinds' rules
            ("granflow.scenarios.plug_flow_rules", "granflow.scenarios.plug_flow_3d"),
            ("granflow.scenarios.column_rules", "granflow.scenarios.channel_column"))

for _rules, _builder in BUILT_IN:
    importlib.import_module(_rules)

__all__ = ["BUILT_IN", "builtin_scenarios", "scenario_text"]
