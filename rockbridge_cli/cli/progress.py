"""Progress of a study run on stderr: a bar with ETA on a terminal, a few plain lines otherwise;
dropped, and the run goes on, once nobody reads it (`output.say`)."""

from __future__ import annotations

import math
import sys
import time

from ..study.work import Finished
from .output import say


class ProgressDisplay:
    """A `study.run.Progress` callback; `assembling` is an `study.run.Assembly` callback.

    On a terminal it redraws one line, ``[#####-----] 12/30  0:03 elapsed  0:05 left``; otherwise
    (a log, CI) it prints a line at every tenth of the run, and `PLAIN_LINE` after the last line
    if no tenth has passed (a spectrum's first round of 1e6 analyses took minutes a tenth, issue
    39). Analyses that did not end ``ok`` are
    reported on a line of their own in both cases. An IDA learns its analyses as it runs: the
    total grows round by round, and the tenths count from the latest total. The time left is
    the pace since the first analysis came back (the start of the workers, and compiling their
    kernels, do not count) times the analyses left; `notice` shows a line of the run's.

    Parameters
    ----------
    heading
        Printed once, before the first analysis is reported (nothing for a run that is refused).
    terminal
        Draw a bar; default: whether stderr is a terminal.
    growing
        Whether the total grows round by round (an IDA, a spectrum): the end of a round then
        shows no time left, which its next rounds would belie.
    """

    WIDTH = 30
    REDRAW = 0.1
    PLAIN_LINE = 60.0
    """Seconds after which a plain line is printed even if no tenth of the run has passed."""
    WRITING_LINE = 10.0
    """Seconds between the plain lines of a long writing of the results file."""
    """Seconds between two redraws of the bar (a study of 10 000 short analyses would otherwise
    redraw it 10 000 times)."""
    SHOWN_PROBLEMS = 10
    """Analyses that did not end ok reported one by one; the rest are counted (the peak table
    has them all)."""

    def __init__(self, heading: str = "", terminal: bool | None = None, growing: bool = False):
        self.heading, self.growing = heading, growing
        self.problems = 0
        self.terminal = sys.stderr.isatty() if terminal is None else terminal
        self.start = time.monotonic()
        self.shown = 0  # tenths of the run reported (plain lines)
        self.total = 0  # analyses the tenths are of
        self.bar_open = False  # a bar drawn without its final newline (terminal)
        self.drawn = -math.inf  # when the bar was last drawn
        self.first: tuple[float, int] | None = None  # when the first batch came back, its count
        self.writing = 0.0  # when the writing of the results file was last reported (plain lines)
        self.said = self.start  # when the last plain line was printed

    def notice(self, text: str) -> None:
        """Show a line of the run's (after the heading, before the bar)."""
        self._head()
        self._line(text)

    def __call__(self, item: Finished, done: int, total: int) -> None:
        self._head()
        if item.status != "ok":
            self.problems += 1
            if self.problems <= self.SHOWN_PROBLEMS:
                self._line(f"{item.bridge} × {item.record}: {item.status}: {item.message}")
            elif self.problems == self.SHOWN_PROBLEMS + 1:
                self._line("more analyses did not end ok: see the peak table's status and message")
        now = time.monotonic()
        elapsed = now - self.start
        if self.first is None or now - self.first[0] < self.REDRAW:  # the first batch's
            self.first = (now if self.first is None else self.first[0], done)
        began, counted = self.first
        left = (now - began) / (done - counted) * (total - done) if done > counted else math.nan
        if self.growing and done == total:  # a round's end: the next rounds are not known yet
            left = math.nan
        if self.terminal:
            if done < total and now - self.drawn < self.REDRAW:
                return
            self.drawn = now
            bar = "#" * (self.WIDTH * done // total)
            self.bar_open = done < total
            say(
                f"\r[{bar:-<{self.WIDTH}}] {done}/{total}  {_clock(elapsed)} elapsed  "
                f"{_clock(left)} left",
                err=True, nl=not self.bar_open,
            )  # fmt: skip
            return
        if total != self.total:  # the start, or a new round of an IDA
            self.total, self.shown = total, 10 * (done - 1) // total
        if 10 * done // total > self.shown or now - self.said >= self.PLAIN_LINE:
            self.shown, self.said = max(self.shown, 10 * done // total), now
            estimate = "" if math.isnan(left) else f", about {left:.0f} s left"
            say(
                f"{done}/{total} analyses ({100 * done // total}%), {elapsed:.1f} s elapsed"
                + estimate,
                err=True,
            )

    def assembling(self, done: int, total: int) -> None:
        """Report the writing of the results file: a bar on a terminal; otherwise its start
        (``done`` 0, or the first block), a line every `WRITING_LINE` seconds, and its end (an
        interrupted run writes fewer analyses than ``total`` and has no end line: the run's
        next line says where they are)."""
        if self.terminal:
            now = time.monotonic()
            if done < total and now - self.drawn < self.REDRAW:
                return
            self.drawn = now
            self.bar_open = done < total
            say(f"\rwriting the results file: {done}/{total}", err=True,
                       nl=not self.bar_open)  # fmt: skip
        elif done == total:
            say(f"writing the results file ({total} analyses): done", err=True)
        elif not self.writing:
            self.writing = time.monotonic()
            say(f"writing the results file (at most {total} analyses): started", err=True)
        elif (now := time.monotonic()) - self.writing >= self.WRITING_LINE:
            self.writing = now
            say(f"writing the results file: {done} analyses written", err=True)

    def close(self) -> None:
        """End a bar that an interruption left unfinished."""
        if self.bar_open:
            say("", err=True)
            self.bar_open = False

    def _head(self) -> None:
        """Print the heading, once."""
        if self.heading:
            say(self.heading, err=True)
            self.heading = ""

    def _line(self, text: str) -> None:
        say(("\r\033[K" if self.terminal else "") + text, err=True)


def _clock(seconds: float) -> str:
    if math.isnan(seconds):
        return "?:??"
    minutes, rest = divmod(int(round(seconds)), 60)
    return f"{minutes}:{rest:02d}"
