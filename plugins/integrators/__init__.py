"""spectrace integrators plugins (see the package docstring of spectrace.plugins)."""
