"""spectrace bsdfs plugins (see the package docstring of spectrace.plugins)."""
