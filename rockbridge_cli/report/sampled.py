"""The report's section of a sampled study (`config.uncertainty`): which sampled field matters
(a saltelli design's Sobol' indices, a tornado's swings), and, with an intensity section, the
fragility folded over the samples."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

from ..errors import InputError
from ..results.sections import IntensitySection
from .markup import escaped, number, table_html


def sampled_section(
    results: Path, design: dict, intensity: IntensitySection | None, figure: Callable[..., str]
) -> str:
    """The section: its heading, a figure and a table where the design gives them.

    Parameters
    ----------
    design
        The study's uncertainty section, as stored.
    intensity
        The study's intensity section, None without.
    figure
        Draws a figure of ``results`` into the page (``figure(plot, results, **options)``).
    """
    from ..assessment.sampled_fragility import folded_fragilities
    from ..assessment.sensitivity import sensitivities, tornadoes
    from ..plots.sensitivity import plot_sensitivity, plot_tornado

    kind = design.get("design", "lhs")
    ida = None if intensity is None else intensity.ida
    states = ida.limit_states if ida is not None else ()
    state = "abutment_failure" if "abutment_failure" in states else (states or ("",))[0]
    quantity = f"capacity:{state}" if ida is not None else "dcr_backfill"
    parts = [f"<h2>Sampled bridges: {escaped(', '.join(design['fields']))}</h2>"]
    try:
        if kind == "saltelli":
            parts.append(_indices(sensitivities(results, quantity)))
            parts.append(f"<figure>{figure(plot_sensitivity, results, quantity=quantity)}"
                         "</figure>")  # fmt: skip
        elif kind == "tornado":
            parts.append(_swings(tornadoes(results, quantity)))
            parts.append(f"<figure>{figure(plot_tornado, results, quantity=quantity)}</figure>")
        else:
            parts.append(f"<p>{len(design['fields'])} fields drawn by a {escaped(kind)} design "
                         f"of {design.get('size')} samples; each sample's values are columns of "
                         "the peak table.</p>")  # fmt: skip
        if intensity is not None and kind != "tornado":
            parts.append(_folded(folded_fragilities(results)))
            parts.append("<p>Each sample's own fragility: rockbridge fragility RESULTS (one row "
                         "per sample and limit state).</p>")  # fmt: skip
    except InputError as exc:  # a study cut short: say so, draw the rest
        parts.append(f"<p>{escaped(exc.problems[0][1])}</p>")
    return "\n".join(parts)


def _indices(found: list) -> str:
    rows = []
    for item in found:
        rows += [[item.bridge, f.field, number(f.first), _interval(f.first_interval),
                  number(f.total), _interval(f.total_interval)] for f in item.fields]  # fmt: skip
    shares = "; ".join(f"{item.bridge} {item.records_share:.2f}" for item in found)
    return (
        f"<p>First- and total-order Sobol' indices of the {escaped(found[0].statistic)} of "
        f"{escaped(found[0].quantity)} over the records, with 90 % bootstrap intervals "
        f"(rockbridge sensitivity). Record-to-record share of its variance: {shares}.</p>"
        + table_html(
            ["bridge", "field", "first order", "90 %", "total order", "90 %"],
            rows,
            text_columns=(0, 1),
        )  # fmt: skip
    )


def _swings(found: list) -> str:
    rows = [[item.bridge, s.field, number(s.values[0]), number(s.values[1]),
             number(s.outputs[0]), number(s.outputs[1]), number(s.swing)]
            for item in found for s in item.swings]  # fmt: skip
    return (
        f"<p>One field at a time at its low and high percentile, the others at their medians: "
        f"the {escaped(found[0].statistic)} of {escaped(found[0].quantity)} (rockbridge "
        "sensitivity), largest swing first.</p>"
        + table_html(
            ["bridge", "field", "low", "high", "output at low", "output at high", "swing"],
            rows,
            text_columns=(0, 1),
        )  # fmt: skip
    )


def _folded(found: list) -> str:
    rows = [[f.folded.bridge, f.folded.limit_state, number(f.folded.median),
             number(f.folded.beta), *(number(b if b == b else None)  # NaN: no fit of their own
                                      for b in (f.beta_rtr, f.beta_u, f.beta_shortcut))]
            for f in found]  # fmt: skip
    return (
        "<p>The fragility over every sample × record (rockbridge fragility --fold-samples), "
        "beside the record-to-record β of the samples' own fits, the β their medians add, and "
        "the shortcut √(β_RTR² + β_U²).</p>"
        + table_html(
            ["bridge", "limit state", "median", "β", "β_RTR", "β_U", "shortcut"],
            rows,
            text_columns=(0, 1),
        )  # fmt: skip
    )


def _interval(bounds: tuple[float, float]) -> str:
    return "-" if bounds[0] != bounds[0] else f"{bounds[0]:.2f}–{bounds[1]:.2f}"
