"""The ``rockbridge`` command line: a thin layer that parses, calls the library and prints.

One module per command family: ``analyze`` (`analysis`), ``describe`` (`bridge`), ``run``,
``peaks``, ``merge`` and a results file's figures (`study`), ``generate-records``,
``select-records`` and the records' figures (`records`), ``fragility`` and its figures
(`fragility`), ``risk`` (`risk`), ``export`` (`export`), ``report`` (`report`), ``sensitivity`` and
its figure (`sensitivity`), ``spectrum`` and its figure (`spectrum`), the parametric figures of a
bridge (`parametric`); what they share to print (`output`) and a run's progress (`progress`).

User errors (bad config, bad record, bad arguments) exit with status 2 and one readable message;
runtime failures exit with status 1; ``--debug`` shows the traceback instead.
"""

from __future__ import annotations

import gc
import os
import shlex
import signal
import sys
import threading

# One thread per process for the linear algebra and OpenMP libraries, set before numpy loads them:
# rockbridge's parallelism is its worker processes, and on a shared machine (a cluster node, a CI
# runner) BLAS threads that spin against other jobs made a two-parameter fit 10-30x slower
# (issue 31). A value the user sets is kept.
for _variable in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_variable, "1")

import click

from .. import __version__
from ..errors import InputError
from ..interrupts import exit_status, stoppable, stopped_by
from ..study.kernels import own_process


class _Group(click.Group):
    """A click group that turns library exceptions into readable messages and exit codes."""

    def parse_args(self, ctx: click.Context, args: list[str]) -> list[str]:
        ctx.meta["rockbridge.argv"] = list(args)  # for the command a refusal suggests
        return super().parse_args(ctx, args)

    def invoke(self, ctx: click.Context):
        try:
            with stoppable():  # SIGTERM and SIGHUP stop a command as Ctrl-C does
                return super().invoke(ctx)
        except InputError as exc:
            if ctx.obj and ctx.obj.get("debug"):
                raise
            click.echo(f"error: {exc}{_way_out(exc, ctx)}", err=True)
            ctx.exit(2)
        except (click.exceptions.Exit, click.exceptions.Abort, click.ClickException):
            raise
        except BrokenPipeError:  # the reader (head, less) went away: nothing left to say
            sys.stderr.close()
            ctx.exit(0)
        except KeyboardInterrupt as stop:
            click.echo(stopped_by(stop), err=True)
            ctx.exit(exit_status(stop))
        except OSError as exc:  # the system refused a file: its message names the file
            if ctx.obj and ctx.obj.get("debug"):
                raise
            click.echo(f"error: {exc}", err=True)
            ctx.exit(1)
        except Exception as exc:  # a runtime failure, not the user's input
            if ctx.obj and ctx.obj.get("debug"):
                raise
            click.echo(
                f"error: {type(exc).__name__}: {exc} (rerun with --debug for details)", err=True
            )
            ctx.exit(1)


def _way_out(error: InputError, ctx: click.Context) -> str:
    """For a config's path refused by the confinement (`config.loading.ConfigFolder`), the one
    command that runs: the same, with the folders it leads to named in ``ROCKBRIDGE_PATHS``."""
    if not error.reach:
        return ""
    named = [f for f in os.environ.get("ROCKBRIDGE_PATHS", "").split(os.pathsep) if f]
    paths = os.pathsep.join(dict.fromkeys((*named, *error.reach)))
    command = shlex.join(["rockbridge", *ctx.meta.get("rockbridge.argv", [])])
    return f"\n  to let it through: ROCKBRIDGE_PATHS={shlex.quote(paths)} {command}"


@click.group(cls=_Group, context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(__version__, prog_name="rockbridge")
@click.option("--debug", is_flag=True, help="Show full tracebacks on errors.")
@click.pass_context
def main(ctx: click.Context, debug: bool) -> None:
    """Seismic response of bridges on rocking piers (Thomaidis, Camara & Kappos 2022)."""
    ctx.ensure_object(dict)
    ctx.obj["debug"] = debug


@main.group()
def plot() -> None:
    """Figures: peaks, histories, spectra, IDA, fragility, sweeps and the paper's parametric
    plots."""


def entry() -> None:
    """The ``rockbridge`` console script: `main`, after which Ctrl-C is left to the system, so
    that one pressed while the interpreter tears down ends it quietly (Python printed
    "Exception ignored … KeyboardInterrupt" and exited 0). The process is rockbridge's own
    (`study.kernels.own_process`). Its objects are then left out of the garbage collector's
    passes (`gc.freeze`): at the interpreter's teardown they went over every object of numba's
    and of the kernels, 0.25 s at the end of any command that had analyzed (a cold `analyze`
    took 1.50 s, 1.24 s without them; ``benchmarks/bench_worker.py --start``)."""
    own_process()
    try:
        main()
    finally:
        if threading.current_thread() is threading.main_thread():
            signal.signal(signal.SIGINT, signal.SIG_DFL)
        gc.freeze()


def _register() -> None:
    # each module adds its commands
    from . import (  # noqa: F401
        analysis,
        bridge,
        export,
        fragility,
        parametric,
        records,
        report,
        risk,
        sensitivity,
        spectrum,
        study,
    )


_register()

if __name__ == "__main__":  # pragma: no cover
    entry()
