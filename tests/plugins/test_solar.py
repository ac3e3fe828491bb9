"""Tests of the solar-position helper of the daylight emitters (``solar``)."""

from __future__ import annotations

from datetime import datetime, timedelta, timezone

import numpy as np
import pytest

from spectrace.errors import ParameterError


def test_spa_paper_example():
    """Reda and Andreas (2004), table A5.1: Golden, Colorado, 2003-10-17 12:30:30 -07:00,
    1830.14 m, 820 mbar, 11 degrees C: topocentric zenith 50.11162, azimuth 194.34024."""
    from spectrace.plugins.emitters import solar

    when = datetime(2003, 10, 17, 12, 30, 30, tzinfo=timezone(timedelta(hours=-7)))
    azimuth, elevation = solar.solar_position(39.742476, -105.1786, when, altitude=1830.14,
                                              pressure=82000.0, temperature=11.0)
    assert azimuth == pytest.approx(194.34024, abs=1e-5)
    assert 90.0 - elevation == pytest.approx(50.11162, abs=1e-5)


def test_naive_datetime_refused():
    """A time without its UTC offset names no instant: refused, naming the parameter."""
    from spectrace.plugins.emitters import solar

    with pytest.raises(ParameterError, match="'datetime' has no UTC offset"):
        solar.parse_datetime("2026-06-21T12:00:00", "ciesky")
    with pytest.raises(ParameterError, match="ISO 8601"):
        solar.parse_datetime("noon", "ciesky")
    assert solar.parse_datetime("2026-06-21T12:00:00Z", "ciesky").utcoffset() == timedelta(0)


def test_frame_and_directions():
    """+Y up: east +X, north -Z; azimuths clockwise from north; +Z up: north +Y."""
    from spectrace.plugins.emitters import solar

    frame = solar.horizon_frame()
    np.testing.assert_allclose(frame, [(1, 0, 0), (0, 0, -1), (0, 1, 0)], atol=1e-15)
    np.testing.assert_allclose(solar.direction(90.0, 0.0, frame), (1, 0, 0), atol=1e-15)
    np.testing.assert_allclose(solar.direction(180.0, 0.0, frame), (0, 0, 1), atol=1e-15)
    np.testing.assert_allclose(solar.direction(0.0, 90.0, frame), (0, 1, 0), atol=1e-15)
    np.testing.assert_allclose(solar.horizon_frame((0, 0, 1))[1], (0, 1, 0), atol=1e-15)


def test_latitude_range():
    """A latitude out of [-90, 90] is refused."""
    from spectrace.plugins.emitters import solar

    with pytest.raises(ParameterError, match="latitude"):
        solar.solar_position(91.0, 0.0, datetime(2026, 1, 1, tzinfo=timezone.utc))
