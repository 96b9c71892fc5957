"""One response-history analysis: a bridge, a ground motion and a fidelity in, a `Response`
out."""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from ._jit import jit
from .bridge import Bridge
from .device_histories import HISTORY_ELONGATION, HISTORY_FORCE, HISTORY_PLASTIC
from .device_mechanics import PEAK_FORCE, PEAK_FORCE_TIME, PEAK_LENGTH, PEAK_LENGTH_TIME
from .devices import BROKEN_AT, YIELDED_AT, Damper, names
from .fidelity import Fidelity, check_work, resolve
from .geometry import Model, kind
from .kinematics import EXACT, Displacements, Kinematics, displacements, simplified
from .memo import BoundedCache
from .quantities import (
    EVENT_NAMES,
    HISTORY_UNITS,
    PEAK_NAMES,
    PEAK_U_DECK,
    PEAK_U_PIER1,
    PEAK_U_PIER2,
    SIGNIFICANT_RATE,
)
from .solver import (
    EVENT_KIND,
    EVENT_MODE,
    EVENT_RATE_AFTER,
    EVENT_RATE_BEFORE,
    EVENT_TIME,
    FAILURE_MODE,
    FREE_FLIGHT,
    IMPACT,
    NO_ERROR,
    NOT_FAILED,
    ONSET,
    POUNDING,
    SOLVER_ERRORS,
    Integration,
    Laws,
    Settings,
    integrate,
)
from .tables import tabulated

TABLE_BYTES = 32 * 2**20
"""What a process keeps of bridges' tabulated kinematics [bytes]: 14 bridges' tables of 2.3 MB.
A study's cells, and so a worker's batches, go bridge by bridge, so a table is used while it is
new; a sweep of a thousand bridges then keeps a worker at the same memory as three bridges do
(the entries' count, `functools.lru_cache`'s bound, let 256 tables grow a worker by 590 MB)."""


def _build_tables(model: Model) -> Kinematics:
    """The tables of a bridge, built without `tables.tabulated`'s own cache (which bounds the
    number of bridges, not their bytes)."""
    return getattr(tabulated, "__wrapped__", tabulated)(model)


_TABLES: BoundedCache[Model, Kinematics] = BoundedCache(
    _build_tables, TABLE_BYTES, lambda kinematics: kinematics.table.nbytes
)


@dataclass
class Response:
    """The response of one bridge to one ground motion, in SI units, in the user's frame.

    Attributes
    ----------
    model : kind of model that ran (``asymmetric-bridge``, ``single-block``, …)
    fidelity : what it ran at, the preset and every knob (`fidelity.resolve`)
    time : sample times of the histories [s]
    histories : name → array at ``time``; units in `HISTORY_UNITS`, and each device's
        (`device_history_names`) in `quantities.DEVICE_HISTORY_UNITS`
    events : dict of arrays: ``time`` [s], ``kind`` (name), ``mode`` after (+1, −1, 0 at rest),
        ``rate_before``, ``rate_after`` (θ̇1 [rad/s])
    peaks : name → (peak value, time [s]); units in `PEAK_UNITS`; NaN for the parts a model
        does not have (a single block has no deck and no pier 2); for each device, its largest
        elongation [m] and force [N] as ``<kind><n>_elongation`` and ``<kind><n>_force``
        (`device_peak_names`), and for a tendon or dissipator whether (1.0 or 0.0) and when it
        first yielded and broke as ``<kind><n>_yielded`` and ``<kind><n>_broken``
    t_onset : time of the first onset of rocking, NaN if the bridge never rocks [s]
    n_impacts, n_poundings : counts of impacts at the rocking interfaces and on the backwall [-]
    failure_mode : `quantities.NO_FAILURE` or one of `quantities.FAILURE_MODES`
    failure_time : time of failure, NaN without [s]
    n_impacts_significant : impacts whose |θ̇1| before the impact exceeds `SIGNIFICANT_RATE` [-]
    dcr_backfill : the paper's demand/capacity ratio, the backfill's deformation over its
        capacity, max(0, max|u_deck| − u_jo)/u_ab; NaN without abutments [-] (docs/model.md §8)
    dcr_overturning : the largest |u| of a pier's centre of gravity over B, its overturning
        limit [-]
    status : ``ok``, or the solver's error message
    solve_time_s : wall time of the integration alone [s]
    steps, rejected_steps : integrator statistics [-]
    """

    model: str
    fidelity: Fidelity
    time: np.ndarray
    histories: dict[str, np.ndarray]
    events: dict[str, np.ndarray]
    peaks: dict[str, tuple[float, float]]
    t_onset: float
    n_impacts: int
    n_poundings: int
    failure_mode: str
    failure_time: float
    n_impacts_significant: int
    dcr_backfill: float
    dcr_overturning: float
    status: str
    solve_time_s: float
    steps: int
    rejected_steps: int

    def peak_row(self) -> dict[str, object]:
        """Flat dictionary of the scalar results (peaks as ``<name>_max`` and ``<name>_time``)."""
        out: dict[str, object] = {}
        for name, (value, when) in self.peaks.items():
            out[f"{name}_max"] = value
            out[f"{name}_time"] = when
        out.update(
            t_onset=self.t_onset, n_impacts=self.n_impacts, n_poundings=self.n_poundings,
            n_impacts_significant=self.n_impacts_significant, failure_mode=self.failure_mode,
            failure_time=self.failure_time, dcr_backfill=self.dcr_backfill,
            dcr_overturning=self.dcr_overturning, status=self.status, model=self.model,
            fidelity=self.fidelity.preset,
            solve_time_s=self.solve_time_s, steps=self.steps, rejected_steps=self.rejected_steps,
        )  # fmt: skip
        return out


def dcr_backfill(model: Model, u_deck: float) -> float:
    """The backfill's demand/capacity ratio, max(0, |u_deck| − u_jo)/u_ab: 0 while the gap stays
    open, 1 at abutment failure; NaN for a bridge without abutments (docs/model.md §8).

    Parameters
    ----------
    u_deck
        The largest |u_deck| of the response [m].
    """
    if not model.has_abutments or not math.isfinite(u_deck):
        return float("nan")
    return max(0.0, u_deck - model.u_jo) / model.u_ab


ABSENT_IN_A_BLOCK = ("u_deck", "v_deck", "theta_deck", "theta2", "u_pier2")
"""The peaks a single block has no part for (its massless twin and deck): NaN in its results."""


def analyze(
    bridge: Bridge,
    acceleration: np.ndarray,
    time_step: float,
    fidelity: str | Fidelity = "default",
    initial: tuple[float, float] = (0.0, 0.0),
    histories: bool = True,
    vertical: np.ndarray | None = None,
    **overrides: object,
) -> Response:
    """Response-history analysis of one bridge under one ground motion.

    Parameters
    ----------
    bridge
        The bridge as analyzed (`config.bridge.BridgeConfig.to_bridge`, or `bridge.Bridge`).
    acceleration
        Ground acceleration at uniform samples, positive to the right [m/s²].
    time_step
        Sample interval of ``acceleration`` [s].
    fidelity
        A preset's name (`fidelity.PRESETS`), or a fidelity settled once (`fidelity.resolve`,
        as a study's analyses take it).
    initial
        Initial rotation θ1 [rad] and angular velocity θ̇1 [rad/s] of the tall pier; non-zero
        values start the bridge rocking at t = 0 (free vibration).
    histories
        False leaves ``time`` and ``histories`` of the response empty (a study that stores
        none): computing the displacements at every sample costs a tenth of a `fast` analysis.
    vertical
        Vertical ground acceleration at the same samples, positive up [m/s²]; None for a record
        without one (the paper's model: docs/model.md §12). Where g + ü_v ≤ 0 the bridge would
        leave the ground: the analysis stops there with a free-flight status.
    overrides
        Fidelity knobs to change (`fidelity.resolve`). ``tail`` [s] continues the analysis after
        the record with zero ground acceleration, so that a bridge still rocking when the record
        ends can come to rest, or fail, within that time.

    Raises
    ------
    TypeError
        ``bridge`` is not a `bridge.Bridge` (a bare `Model` does not say which way it faces),
        the accelerations or the time step are not real numbers, or a record is given in place
        of its accelerations.
    ValueError
        An empty, non-finite, too short or not one-dimensional record, a vertical component not
        of its length or not finite, a non-positive time step, a knob out of its range
        (`fidelity.LIMITS`), or an analysis too long for them (`fidelity.check_work`).
    """
    if not isinstance(bridge, Bridge):
        raise TypeError(
            f"analyze takes a Bridge (BridgeConfig.to_bridge() or core.bridge.Bridge), not "
            f"{type(bridge).__name__}: a bare model does not say whether it is mirrored"
        )
    acceleration = _ground(acceleration, time_step)  # its errors before the fidelity's
    chosen = resolve(fidelity, **overrides) if isinstance(fidelity, str) else (
        fidelity.changed(**overrides) if overrides else fidelity
    )  # fmt: skip
    ground = ground_motion(acceleration, time_step, chosen, bridge.model.g, vertical)
    prepared = prepare(bridge, chosen)
    result, solve_time = solve(prepared, ground.acc, time_step, ground.up, initial)
    if ground.flight is not None:
        result = _before_flight(
            result, ground.flight, ground.samples, time_step, chosen.knobs["output_step"]
        )
    return _response(prepared, result, solve_time, histories)


class Prepared(NamedTuple):
    """What every analysis of one bridge at one fidelity shares, whatever its ground motion
    (`prepare`): a study's batch computes it once per bridge, `analyze` once per call.

    Attributes
    ----------
    bridge : the bridge
    fidelity : the fidelity, settled (`fidelity.resolve`)
    kin : the kinematics its preset names (exact, tabulated or simplified)
    laws : the bridge's onset thresholds, restitution and pounding laws (`Bridge.laws`)
    settings : the solver's settings of the fidelity (`Fidelity.settings`)
    devices : the devices' table (`Bridge.device_table`), None without devices
    """

    bridge: Bridge
    fidelity: Fidelity
    kin: Kinematics
    laws: Laws
    settings: Settings
    devices: np.ndarray | None


def prepare(bridge: Bridge, fidelity: Fidelity) -> Prepared:
    """What the analyses of ``bridge`` at ``fidelity`` share (`Prepared`).

    Raises
    ------
    ValueError
        The bridge's restitution does not reverse the rocking (`Bridge.laws`).
    """
    kin, laws = _kinematics(bridge.model, fidelity.knobs["kinematics"]), bridge.laws()
    return Prepared(bridge, fidelity, kin, laws, fidelity.settings(), bridge.device_table())


class GroundMotion(NamedTuple):
    """A ground motion as the integrator takes it (`ground_motion`).

    Attributes
    ----------
    acc : horizontal ground acceleration, with the fidelity's tail of rest or cut before a
        free flight [m/s²]
    up : vertical ground acceleration at the same samples, None without [m/s²]
    flight : the first sample at which the bridge would leave the ground, None if never
    samples : the record's samples, before the tail or the cut [-]
    """

    acc: np.ndarray
    up: np.ndarray | None
    flight: int | None
    samples: int


def ground_motion(
    acceleration: np.ndarray,
    time_step: float,
    fidelity: Fidelity,
    g: float,
    vertical: np.ndarray | None = None,
) -> GroundMotion:
    """A record checked (`analyze`'s errors) and made the integrator's ground motion; arguments
    as in `analyze`, ``g`` the bridge's gravity [m/s²], which decides a free flight."""
    acc, knobs = check_motion(acceleration, time_step, fidelity), fidelity.knobs
    up = None if vertical is None else _vertical(vertical, acc.size)
    samples, flight = acc.size, None if up is None else _flight(up, g)
    acc, up = _integrated(acc, up, flight, int(round(knobs["tail"] / time_step)))
    return GroundMotion(acc, up, flight, samples)


def check_motion(acceleration: np.ndarray, time_step: float, fidelity: Fidelity) -> np.ndarray:
    """A horizontal record as a float array, checked as `analyze` checks it at ``fidelity``
    (its errors) [m/s²]; ``time_step`` [s]."""
    acc = _ground(acceleration, time_step)
    check_work(fidelity.knobs, acc.size, time_step)
    return acc


def solve(
    prepared: Prepared,
    acc: np.ndarray,
    time_step: float,
    up: np.ndarray | None = None,
    initial: tuple[float, float] = (0.0, 0.0),
) -> tuple[Integration, float]:
    """The integration of a prepared bridge under a ground motion (`ground_motion`'s ``acc`` and
    ``up``) in the core's frame, and its wall time [s]; ``initial`` as in `analyze`."""
    model, sign = prepared.bridge.model, prepared.bridge.sign
    start = time.perf_counter()
    arguments = (
        model, prepared.laws, prepared.kin, sign * acc, float(time_step), prepared.settings,
        sign * float(initial[0]), sign * float(initial[1]),
    )  # fmt: skip
    # the vertical motion is the same in the mirror image
    if prepared.devices is not None:  # kernels compiled for devices, only for a bridge with some
        result = integrate(*arguments, up, prepared.devices)
    else:
        result = integrate(*arguments) if up is None else integrate(*arguments, up)
    return result, time.perf_counter() - start


class Events(NamedTuple):
    """An analysis's events in the user's frame, one entry per event: ``time`` [s], ``kind`` (a
    code of `EVENT_NAMES`), ``mode`` after (+1, −1, 0 at rest), ``rate_before``, ``rate_after``
    (θ̇1 [rad/s])."""

    time: np.ndarray
    kind: np.ndarray
    mode: np.ndarray
    rate_before: np.ndarray
    rate_after: np.ndarray


class Summary(NamedTuple):
    """What an integration says besides its histories, in the user's frame (`summary`): all a
    study that keeps no histories stores of it but the devices' peaks and the timings.
    Attributes as `Response`'s of the same names; ``peaks`` (len(`PEAK_NAMES`), 2) each
    quantity's peak and its time [s], NaN where the model has no such part or where the
    integrator stopped early; ``events`` as `Events`."""

    model: str
    peaks: np.ndarray
    events: Events
    t_onset: float
    n_impacts: int
    n_poundings: int
    failure_mode: str
    failure_time: float
    n_impacts_significant: int
    dcr_backfill: float
    dcr_overturning: float
    status: str
    steps: int
    rejected_steps: int


def summary(bridge: Bridge, result: Integration) -> Summary:
    """The `Summary` of an integration of ``bridge`` (`solver.Integration`, whose peaks it masks
    in place)."""
    model, sign = bridge.model, bridge.sign
    events, peaks = result.events, result.peaks
    if kind(model) == "single-block":  # the block's massless twin and deck are not results
        peaks[[PEAK_NAMES.index(name) for name in ABSENT_IN_A_BLOCK]] = np.nan
    kinds = events[:, EVENT_KIND].astype(int)
    if result.error != NO_ERROR:  # the integrator stopped early: no peak of the record is known
        peaks[:] = np.nan
    impacts_at = kinds == IMPACT
    onsets = events[kinds == ONSET, EVENT_TIME]
    u_pier2 = peaks[PEAK_U_PIER2, 0] if model.m2 else 0.0
    return Summary(
        model=kind(model),
        peaks=peaks,
        events=Events(
            events[:, EVENT_TIME],
            kinds,
            sign * events[:, EVENT_MODE],
            sign * events[:, EVENT_RATE_BEFORE],
            sign * events[:, EVENT_RATE_AFTER],
        ),  # fmt: skip
        t_onset=float(onsets[0]) if onsets.size else float("nan"),
        n_impacts=int(np.count_nonzero(impacts_at)),
        n_poundings=int(np.count_nonzero(kinds == POUNDING)),
        failure_mode=FAILURE_MODE[result.failure],
        failure_time=float(result.end_time) if result.failure != NOT_FAILED else float("nan"),
        n_impacts_significant=int(
            np.count_nonzero(np.abs(events[impacts_at, EVENT_RATE_BEFORE]) > SIGNIFICANT_RATE)
        ),
        dcr_backfill=dcr_backfill(model, peaks[PEAK_U_DECK, 0]),
        dcr_overturning=max(peaks[PEAK_U_PIER1, 0], u_pier2) / model.B,
        status=_status(result),
        steps=int(result.steps),
        rejected_steps=int(result.rejected),
    )


_SCALARS = tuple(name for name in Summary._fields if name not in ("model", "peaks", "events"))
"""The fields a `Response` takes from its `Summary` as they are."""


def _response(
    prepared: Prepared, result: Integration, solve_time: float, histories: bool
) -> Response:
    """The `Response` of an integration (`solver.Integration`) in the user's frame; arguments as
    in `analyze`, ``solve_time`` [s] the wall time of the integration."""
    bridge = prepared.bridge
    model, sign, kin = bridge.model, bridge.sign, prepared.kin
    found = summary(bridge, result)
    times, stored = np.zeros(0), {}
    if histories:
        times = np.arange(result.theta1.size) * prepared.fidelity.knobs["output_step"]
        stored = {**_histories(model, kin, sign, result), **_device_histories(bridge, result)}
    events, peaks = found.events, found.peaks
    return Response(
        model=found.model,
        fidelity=prepared.fidelity,
        time=times,
        histories=stored,
        events={
            "time": events.time,
            "kind": np.array([EVENT_NAMES[i] for i in events.kind], dtype=object),
            "mode": events.mode,
            "rate_before": events.rate_before,
            "rate_after": events.rate_after,
        },
        peaks={
            **{name: (float(peaks[i, 0]), float(peaks[i, 1])) for i, name in enumerate(PEAK_NAMES)},
            **device_peaks(bridge, result),
        },
        solve_time_s=solve_time,
        **{name: getattr(found, name) for name in _SCALARS},
    )


def device_peak_names(bridge: Bridge) -> list[tuple[str, str]]:
    """Each device's names in a `Response`'s peaks, (elongation, force): ``tendon1``, ``damper1``,
    … numbered by kind in the bridge's order."""
    return [(f"{stem}_elongation", f"{stem}_force") for stem in names(bridge.devices)]


def device_history_names(bridge: Bridge) -> list[dict[str, int]]:
    """Each device's names in a `Response`'s histories, with the column of the integrator's
    (`device_histories.HISTORY_FORCE` …): ``<name>_force``, ``<name>_elongation`` and, but for a
    damper, ``<name>_plastic``; ``<name>`` as in `device_peak_names`."""
    columns = {"force": HISTORY_FORCE, "elongation": HISTORY_ELONGATION, "plastic": HISTORY_PLASTIC}
    return [
        {f"{stem}_{what}": column for what, column in columns.items()
         if what != "plastic" or not isinstance(device, Damper)}
        for stem, device in zip(names(bridge.devices), bridge.devices, strict=True)
    ]  # fmt: skip


def _device_histories(bridge: Bridge, result: Integration) -> dict[str, np.ndarray]:
    """Each device's force [N], elongation [m] and plastic elongation [m] at the samples, by name
    (`device_history_names`); none without devices. Both are the same in a mirror image."""
    out = {}
    for i, named in enumerate(device_history_names(bridge)):
        for name, column in named.items():
            out[name] = result.device_histories[:, i, column].copy()
    return out


def device_peaks(bridge: Bridge, result: Integration) -> dict[str, tuple[float, float]]:
    """The devices' peaks of an integration, by name (`device_peak_names`), and for a tendon or
    dissipator whether it yielded and broke (ruptured, fractured), as ``<name>_yielded`` and
    ``<name>_broken``: (1.0, the first time) or (0.0, NaN), from the solver's state; NaN where the
    integrator stopped early."""
    rows, states = result.device_peaks, result.devices
    if states is None:  # no devices
        return {}
    if result.error != NO_ERROR:  # the integrator stopped early: no peak of the record is known
        rows, states = np.full_like(rows, np.nan), np.full_like(states, np.nan)
    out = {}
    for (length, force), row, state, device in zip(
        device_peak_names(bridge), rows, states, bridge.devices, strict=True
    ):
        out[length] = (float(row[PEAK_LENGTH]), float(row[PEAK_LENGTH_TIME]))
        out[force] = (float(row[PEAK_FORCE]), float(row[PEAK_FORCE_TIME]))
        if not isinstance(device, Damper):
            stem = length.removesuffix("_elongation")
            for suffix, column in (("_yielded", YIELDED_AT), ("_broken", BROKEN_AT)):
                when = float(state[column])
                reached = math.nan if result.error != NO_ERROR else float(not math.isnan(when))
                out[stem + suffix] = (reached, when)
    return out


def _integrated(
    acc: np.ndarray, up: np.ndarray | None, flight: int | None, tail: int
) -> tuple[np.ndarray, np.ndarray | None]:
    """The ground motion the integrator takes: with ``tail`` samples of rest after it or, where
    the bridge would take flight at sample ``flight``, up to the sample before (one, if at once)."""
    if flight is None:
        rest = np.zeros(tail)
        return np.concatenate([acc, rest]), None if up is None else np.concatenate([up, rest])
    assert up is not None, "only a vertical motion lifts the bridge off"
    end = max(flight, 1)
    return np.array(acc[:end]), np.array(up[:end])  # copies: a read-only view compiles anew


def _ground(acceleration: np.ndarray, time_step: float) -> np.ndarray:
    """The horizontal ground motion as a float array, checked (`analyze`'s errors) [m/s²]."""
    if hasattr(acceleration, "acceleration") and hasattr(acceleration, "time_step"):
        raise TypeError("analyze takes a record's accelerations and time step "
                        "(record.acceleration, record.time_step), not the record")  # fmt: skip
    if np.iscomplexobj(acceleration) or not isinstance(time_step, (int, float, np.number)):
        raise TypeError("analyze takes real accelerations [m/s²] and a real time step [s]")
    acc = np.ascontiguousarray(acceleration, dtype=float)
    if acc.ndim != 1:
        raise ValueError(f"the ground motion is a 1-D array of accelerations, not of shape "
                         f"{acc.shape} (a column of times beside them?)")  # fmt: skip
    if acc.size < 2:
        raise ValueError("the ground motion needs at least two samples")
    if not np.all(np.isfinite(acc)):
        raise ValueError("the ground motion has non-finite values")
    if not (time_step > 0.0 and np.isfinite(time_step)):
        raise ValueError(f"the time step must be positive, got {time_step}")
    return acc


def _vertical(vertical: np.ndarray, samples: int) -> np.ndarray:
    """A vertical component checked against a horizontal one of ``samples`` samples [m/s²]."""
    if np.iscomplexobj(vertical):
        raise TypeError("analyze takes real vertical accelerations [m/s²]")
    up = np.ascontiguousarray(vertical, dtype=float)
    if up.shape != (samples,):
        raise ValueError(
            f"the vertical ground motion has {up.size} samples, the horizontal {samples}: "
            "they must share their samples"
        )
    if not np.all(np.isfinite(up)):
        raise ValueError("the vertical ground motion has non-finite values")
    return up


def _flight(vertical: np.ndarray, g: float) -> int | None:
    """The first sample at which g + ü_v ≤ 0, where the bridge would leave the ground, or None."""
    lifted = np.flatnonzero(g + vertical <= 0.0)
    return int(lifted[0]) if lifted.size else None


def _before_flight(
    result: Integration, flight: int, samples: int, time_step: float, output_step: float
) -> Integration:
    """An integration that stopped before a free flight at sample ``flight`` of a record of
    ``samples`` samples at ``time_step`` [s], as the record's: its histories NaN after its end
    (every ``output_step`` [s]), and `FREE_FLIGHT` with the flight's time, unless it stopped
    before (docs/model.md §12)."""
    count = int(np.floor((samples - 1) * time_step / output_step + 1e-9)) + 1  # as `integrate`
    missing = count - result.theta1.size
    devices = result.device_histories
    stretched = result._replace(
        theta1=np.concatenate([result.theta1, np.full(missing, np.nan)]),
        rate=np.concatenate([result.rate, np.full(missing, np.nan)]),
        mode=np.concatenate([result.mode, np.zeros(missing, dtype=result.mode.dtype)]),
        device_histories=np.concatenate([devices, np.full((missing, *devices.shape[1:]), np.nan)]),
    )
    if result.failure != NOT_FAILED or result.error != NO_ERROR:
        return stretched
    return stretched._replace(error=FREE_FLIGHT, end_time=flight * time_step)


def _status(result: Integration) -> str:
    """``ok``, or why the integrator stopped early (`SOLVER_ERRORS`; a free flight with when)."""
    if result.error == FREE_FLIGHT:
        return f"{SOLVER_ERRORS[FREE_FLIGHT]} (at t = {result.end_time:.6g} s)"
    return SOLVER_ERRORS[result.error]


_DISPLACEMENTS = len(Displacements._fields)


def _histories(
    model: Model, kin: Kinematics, sign: float, result: Integration
) -> dict[str, np.ndarray]:
    """The histories of `HISTORY_UNITS` from the integrator's θ1, θ̇1 and modes, in the user's
    frame."""
    observed = _observe(model, kin, result.theta1, result.mode).T
    track = dict(zip(Displacements._fields, observed, strict=True))
    columns = {"theta1": result.theta1, "theta1_rate": result.rate, "mode": result.mode, **track}
    histories = {  # in a mirror image all but the vertical motions change sign
        name: columns[name] if name.startswith("v_") else sign * columns[name]
        for name in HISTORY_UNITS
    }
    if kind(model) == "single-block":  # the block's massless twin and deck are not results
        for name in ("theta2", "theta_deck", "u_deck", "v_deck", "u_pier2", "v_pier2"):
            histories[name] = np.full_like(result.theta1, np.nan)
    return histories


def _kinematics(model: Model, name: str) -> Kinematics:
    """The kinematics a fidelity preset names: exact, tabulated or simplified (the paper's)."""
    if name == "tabulated":
        return _TABLES(model)
    return simplified(model) if name == "simplified" else EXACT


@jit
def _observe(model: Model, kin: Kinematics, theta1: np.ndarray, mode: np.ndarray) -> np.ndarray:
    """`Displacements` at every sample, one column per field: shape (n, 8)."""
    out = np.zeros((theta1.size, _DISPLACEMENTS))
    for i in range(theta1.size):
        if not np.isfinite(theta1[i]):
            out[i, :] = np.nan
        elif mode[i] != 0:
            values = displacements(model, float(mode[i]), theta1[i], kin)
            for j in range(_DISPLACEMENTS):
                out[i, j] = values[j]
    return out
