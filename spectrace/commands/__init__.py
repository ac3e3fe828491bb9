"""The ``spectrace`` subcommands, one module per subcommand, imported only by :mod:`spectrace.cli`.

Each module has ``add_arguments(parser)`` and ``run(args) -> int``: it parses, calls the
library (``spectrace.*``, ``spectrace.spectral``, ``spectrace.photometry``) and prints.
Nothing else imports a command.
"""
