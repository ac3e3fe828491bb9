"""The check every command-line error test makes (a plain module, importable from any test
file: pytest puts this folder on ``sys.path`` for its ``conftest.py``).

A command's mistake ends stderr with ONE line ``error: ...`` naming the problem, and no
traceback (the developers' guide: bad input is a one-line error, exit status 2)."""

from __future__ import annotations


def assert_one_line_error(capsys, *words: str, alone: bool = False) -> str:
    """The captured stderr ends in one line ``error: ...`` holding each of ``words``, and
    holds no traceback; with ``alone`` that line is all of stderr (no progress or
    ``measuring ...`` line before it). Returns the line."""
    err = capsys.readouterr().err.strip().splitlines()
    assert err and err[-1].startswith("error: "), err
    assert "Traceback" not in "\n".join(err), err
    assert not alone or len(err) == 1, err
    for word in words:
        assert word in err[-1], (word, err[-1])
    return err[-1]
