"""spectrace emitters plugins (see the package docstring of spectrace.plugins)."""
