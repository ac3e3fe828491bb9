"""Mitsuba's log through Python's logging (issue 18 A7): once per message kind, quiet at the
command line unless -v, and a user's own appenders left alone."""

from __future__ import annotations

import logging

import pytest

from spectrace import mitsuba_log
from spectrace.cli import main

#: An ldsampler asked for 5 samples warns that it rounds them to 16 (a power of 4).
LD_SCENE = """<scene version="3.0.0">
    <integrator type="path"/>
    <sensor type="perspective">
        <film type="hdrfilm"><integer name="width" value="4"/><integer name="height" value="4"/>
        </film>
        <sampler type="ldsampler"><integer name="sample_count" value="5"/></sampler>
    </sensor>
    <shape type="sphere"/>
</scene>"""
ROUNDING = "[LowDiscrepancySampler] Sample count should be"


@pytest.fixture
def fresh_kinds(monkeypatch):
    """No message kind seen yet (other tests of the session log the same warnings)."""
    monkeypatch.setattr(mitsuba_log, "_seen", set())


def test_each_kind_is_logged_once(fresh_kinds, monkeypatch):
    """Mitsuba's time and level prefix is dropped; messages that differ only in numbers
    are one kind, logged once on the 'spectrace.mitsuba' logger."""
    log = logging.getLogger(mitsuba_log.LOGGER)
    records = []
    handler = logging.Handler()
    handler.emit = records.append
    monkeypatch.setattr(log, "handlers", [handler])
    monkeypatch.setattr(log, "level", logging.WARNING)
    line = "2026-01-01 12:00:00 WARN  [LowDiscrepancySampler] rounding to {}"
    assert mitsuba_log.forward(logging.WARNING, line.format(64))
    assert not mitsuba_log.forward(logging.WARNING, line.format(16))
    assert mitsuba_log.forward(logging.WARNING, "[HDRFilm] Monochrome mode enabled")
    assert [r.getMessage() for r in records] == ["[LowDiscrepancySampler] rounding to 64",
                                                  "[HDRFilm] Monochrome mode enabled"]
    assert [r.levelno for r in records] == [logging.WARNING] * 2


class _Logger:
    """Mitsuba's logger as route() sees it."""

    def __init__(self, appenders):
        self.appenders = list(appenders)

    def appender_count(self):
        return len(self.appenders)

    def appender(self, i):
        return self.appenders[i]

    def clear_appenders(self):
        self.appenders.clear()

    def add_appender(self, appender):
        self.appenders.append(appender)


def test_a_users_appenders_are_left_alone(monkeypatch):
    """route() replaces Mitsuba's default stream appender, once per process; a logger with
    the user's own appender (or two appenders) is not touched."""
    import mitsuba as mi

    class Fake:
        Appender = mi.Appender
        StreamAppender = type("StreamAppender", (), {})

    class Mine:  # the user's appender
        pass

    monkeypatch.setattr(mitsuba_log, "_appender", None)
    for appenders in ([Mine()], [Fake.StreamAppender(), Mine()]):
        logger = _Logger(appenders)
        Fake.logger = staticmethod(lambda logger=logger: logger)
        assert not mitsuba_log.route(Fake)
        assert logger.appenders == appenders
    logger = _Logger([Fake.StreamAppender()])
    Fake.logger = staticmethod(lambda: logger)
    assert mitsuba_log.route(Fake)
    assert len(logger.appenders) == 1 and isinstance(logger.appenders[0], mi.Appender)
    logger.appenders = [Fake.StreamAppender()]  # what the user does after is theirs
    assert not mitsuba_log.route(Fake)


@pytest.mark.parametrize(("flags", "count"), [([], 0), (["-v"], 1)])
def test_command_line_is_quiet_unless_verbose(tmp_path, capsys, fresh_kinds, flags, count):
    """`spectrace render` does not show Mitsuba's warnings; with -v it shows each once."""
    import spectrace

    spectrace.set_variant("llvm_ad_rgb")
    if mitsuba_log._appender is None:
        pytest.skip("Mitsuba's log was set up by someone else in this process")
    scene = tmp_path / "ld.xml"
    scene.write_text(LD_SCENE)
    code = main(["render", str(scene), "--variant", "llvm_ad_rgb", "--spp", "10",
                 "--spp-per-pass", "5", "-q", "-o", str(tmp_path / "ld.exr"), *flags])
    assert code == 0
    err = capsys.readouterr().err
    assert err.count(ROUNDING) == count, err
