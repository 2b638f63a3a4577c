"""Configuration: the schema, the cross-field rules, the messages and the layered loading.

Imports point one way: ``schema`` and ``messages`` at the bottom, ``rules`` on them,
``loading`` (with ``Config``) on top; this face hands the public names on.
"""

from granflow.config.cost import estimated_triangles
from granflow.config.loading import (
    CUSTOM,
    MAX_TOML_BYTES,
    TOML_HEADER,
    Config,
    apply_overrides,
    config_to_toml,
    load_config,
    parse_value,
    read_toml_file,
    toml_literal,
)
from granflow.config.rules import MAX_TRIANGLES, inert_keys
from granflow.config.scenario_files import builtin_scenarios, scenario_text
from granflow.config.schema import SECTIONS, ConfigError, ConfigNote

__all__ = ["CUSTOM", "MAX_TOML_BYTES", "MAX_TRIANGLES", "SECTIONS", "TOML_HEADER", "Config",
           "ConfigError", "ConfigNote", "apply_overrides", "builtin_scenarios", "config_to_toml",
           "estimated_triangles", "inert_keys", "load_config", "parse_value", "read_toml_file",
           "scenario_text", "toml_literal"]
