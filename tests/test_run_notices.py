"""A run says so when it waits, after its analyses, for its description's numerics (a set of
many records, or of pairs swept over angles, kept a new user 18 s after "100 %" without a word)."""

from __future__ import annotations

import time

from rockbridge_cli.study import run


def test_a_slow_wait_for_the_description_is_announced_once(monkeypatch):
    said: list[str] = []
    monkeypatch.setattr(run, "SLOW_S", 0.01)
    with run._said_if_slow(said.append, run.DESCRIBING):
        time.sleep(0.5)  # fifty times the threshold: the timer's thread has fired
    assert said == [run.DESCRIBING]


def test_a_quick_one_is_not(monkeypatch):
    said: list[str] = []
    monkeypatch.setattr(run, "SLOW_S", 30.0)
    with run._said_if_slow(said.append, run.DESCRIBING):
        pass
    time.sleep(0.05)
    assert said == []
