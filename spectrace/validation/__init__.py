"""``spectrace.validation``: the analytical test cases of lighting-program validation
(CIE 171:2006 families), each a scene with its closed-form answer.

:func:`run` measures cases and returns their :class:`~spectrace.validation.cases.Result`;
:mod:`~spectrace.validation.cases` defines them, :mod:`~spectrace.validation.reference`
holds the closed forms and :mod:`~spectrace.validation.report` writes ``report.md``; the
points are measured as ``spectrace lux --points`` measures them
(:mod:`spectrace.lighting.points`, :mod:`spectrace.lighting.luminance`).
"""

from __future__ import annotations

from spectrace.errors import ParameterError


def run(names=None, *, quick: bool = False, seed: int = 0, params=None, progress=None):
    """Run the cases ``names`` (default: all, in order) and return their results. The
    variant must be set (``spectrace.set_variant``). ``params`` override the scenes' XML
    parameters (never the references); ``progress(name)`` is called before each case."""
    from spectrace.validation.cases import CASES, Result, Settings

    names = list(CASES) if not names else list(names)
    unknown = [n for n in names if n not in CASES]
    if unknown:
        raise ParameterError(f"validation: unknown case {unknown[0]!r} (cases: "
                             f"{', '.join(CASES)})")
    settings = Settings(quick=quick, seed=seed, params=dict(params or {}))
    results: list[Result] = []
    for name in names:
        if progress is not None:
            progress(name)
        results.append(CASES[name](settings))
    return results
