"""The one exception type for mistakes a user can make (bad file, bad parameter).

The command line turns it into a one-line ``error: ...`` on stderr and exit status 2.
"""


class UserError(Exception):
    """A mistake in the user's input: the message names the file or parameter."""
