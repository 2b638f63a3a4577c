"""Built-in scenarios (TOML package data) and their registry."""

from granflow.config.scenario_files import builtin_scenarios, scenario_text

__all__ = ["builtin_scenarios", "scenario_text"]
