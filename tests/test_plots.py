"""The figures: the parametric curves against the paper's published values (docs/model.md §10), and
every figure written in each format, with its labels and units."""

from __future__ import annotations

import re

import matplotlib
import numpy as np
import pytest
from conftest import fresh_python
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from studies import BRIDGES, SLENDER_BLOCK, STUDIED, write_study

from rockbridge_cli.config.bridge import load_bridge
from rockbridge_cli.config.study import load_study
from rockbridge_cli.core.geometry import ratios
from rockbridge_cli.errors import InputError
from rockbridge_cli.paths import written_by_rockbridge
from rockbridge_cli.plots import parametric
from rockbridge_cli.plots.history import plot_history
from rockbridge_cli.plots.peaks import plot_peaks
from rockbridge_cli.results import read_peaks
from rockbridge_cli.study.run import run_study

MAGIC = {".png": b"\x89PNG", ".pdf": b"%PDF", ".svg": b"<?xml"}


@pytest.fixture(scope="module")
def done(tmp_path_factory):
    folder = tmp_path_factory.mktemp("figures")
    study = load_study(write_study(folder, extra="output: {path: out.h5}\n"))
    run_study(study, workers=1)
    return study.output


def svg_text(path) -> str:
    return path.read_text(encoding="utf-8")


# --- the curves against the paper (docs/model.md §10, "from the corrected equations") ----------


def test_onset_fig3():
    """Fig. 3: 0.10 g at h̄ = 1 in both directions; 0.336 g (p) and 0.361 g (n) at h̄ = 6.4."""
    config = load_bridge(BRIDGES / "fig3-hbar6.4.yaml")
    curves = parametric.onset_curves(config, np.array([1.0, 6.4]))
    np.testing.assert_allclose(curves["p"], [0.1000, 0.336], atol=6e-4)
    np.testing.assert_allclose(curves["n"], [0.1000, 0.361], atol=6e-4)


def test_onset_of_the_studied_bridges():
    """Studied bridges: 0.1118 / 0.1128 g at h̄ = 1.25, 0.1456 / 0.1497 g at h̄ = 2."""
    config = load_bridge(BRIDGES / "studied-hbar1.00.yaml")
    curves = parametric.onset_curves(config, np.array([1.25, 2.0]))
    np.testing.assert_allclose(curves["p"], [0.1118, 0.1456], atol=6e-5)
    np.testing.assert_allclose(curves["n"], [0.1128, 0.1497], atol=6e-5)


def test_short_pier_variation_reproduces_table1():
    """Table 1: m_pier,2 = 35.15·10⁴ and 21.97·10⁴ kg; q = 0.7708 and 0.7858·10⁻³ m/kN."""
    model = load_bridge(BRIDGES / "studied-hbar1.00.yaml").to_bridge().model
    for h_bar, mass, q in ((1.25, 35.15e4, 0.7708e-6), (2.0, 21.97e4, 0.7858e-6)):
        variant = parametric.with_short_pier(model, h_bar)
        assert variant.m2 == pytest.approx(mass, rel=2e-4)
        assert ratios(variant)["q"] == pytest.approx(q, rel=2e-4)
        built = load_bridge(BRIDGES / f"studied-hbar{h_bar:.2f}.yaml").to_bridge().model
        assert variant.I2 == pytest.approx(built.I2, rel=1e-12)


def test_q_fig4():
    """Fig. 4: q(h̄ = 5)/q(h̄ = 1) − 1 = 5.3 % (the paper's "4 %" is not reproducible)."""
    model = load_bridge(BRIDGES / "studied-hbar1.00.yaml").to_bridge().model
    change = ratios(parametric.with_short_pier(model, 5.0))["q"] / ratios(model)["q"] - 1
    assert change == pytest.approx(0.053, abs=5e-4)


def test_restitution_fig7():
    """Fig. 7: (η_bridge − η_frame)/η_bridge = 0.41 % at h̄ = 1 and 12.7 % at h̄ = 5 (p→n)."""
    config = load_bridge(BRIDGES / "fig8-hbar1.5.yaml")
    model = config.to_bridge().model
    variants = [parametric.with_short_pier(model, h) for h in (1.0, 5.0)]
    curves = parametric.restitution_curves(config, variants)
    gain = (curves["bridge p→n"] - curves["frame p→n"]) / curves["bridge p→n"]
    np.testing.assert_allclose(gain, [0.0041, 0.127], atol=5e-4)
    assert np.all(curves["bridge n→p"] > curves["frame n→p"])


def test_restitution_vs_spans_fig8():
    """Fig. 8A (L2 = 45): L1 = 15 m 0.9829 / 0.9798, 90 m 0.9879 / 0.9847; Fig. 8B (L1 = 45):
    L2 = 15 m p→n 0.9890, 90 m 0.9843."""
    config = load_bridge(BRIDGES / "fig8-hbar1.5.yaml")
    model = config.to_bridge().model
    side = parametric.restitution_curves(
        config, [model._replace(L1=15.0), model._replace(L1=90.0)], frame=False
    )
    np.testing.assert_allclose(side["bridge p→n"], [0.9829, 0.9879], atol=6e-5)
    np.testing.assert_allclose(side["bridge n→p"], [0.9798, 0.9847], atol=6e-5)
    central = parametric.restitution_curves(
        config, [model._replace(L2=15.0), model._replace(L2=90.0)], frame=False
    )
    np.testing.assert_allclose(central["bridge p→n"], [0.9890, 0.9843], atol=6e-5)


def test_directions_follow_the_tall_pier(tmp_path):
    """A bridge drawn with its tall pier on the right is the mirror image (docs/model.md §1): its
    p and n curves are those of the original swapped."""
    text = (BRIDGES / "studied-hbar2.00.yaml").read_text(encoding="utf-8")
    mirrored = tmp_path / "mirrored.yaml"
    mirrored.write_text(text.replace("[26.0, 13.0]", "[13.0, 26.0]"), encoding="utf-8")
    h_bars = np.array([1.5, 3.0])
    left = parametric.onset_curves(load_bridge(BRIDGES / "studied-hbar2.00.yaml"), h_bars)
    right = parametric.onset_curves(load_bridge(mirrored), h_bars)
    np.testing.assert_array_equal(right["p"], left["n"])
    np.testing.assert_array_equal(right["n"], left["p"])


# --- the figure files --------------------------------------------------------------------


@pytest.mark.slow
@pytest.mark.parametrize("suffix", [".png", ".pdf", ".svg"])
def test_parametric_figures(tmp_path, suffix):
    for name in ("onset", "q", "restitution", "spans"):
        draw = getattr(parametric, f"plot_{name}")
        path = draw(BRIDGES / "fig8-hbar1.5.yaml", tmp_path / f"{name}{suffix}")
        assert path.read_bytes().startswith(MAGIC[suffix]), name
        assert written_by_rockbridge(path), name  # so that the next figure may replace it
    foreign = tmp_path / f"foreign{suffix}"  # the same format, from another program
    figure = Figure()
    FigureCanvasAgg(figure)
    figure.savefig(foreign)
    before = foreign.read_bytes()
    assert not written_by_rockbridge(foreign)
    with pytest.raises(InputError, match="is not a figure rockbridge wrote: not replaced"):
        parametric.plot_onset(BRIDGES / "fig8-hbar1.5.yaml", foreign)
    assert foreign.read_bytes() == before


@pytest.mark.parametrize("bridge", ["fig3-hbar6.4", "fig8-hbar1.5", "studied-hbar2.00"])
def test_the_short_pier_axis_of_figs_3_and_7_has_labels_that_do_not_collide(
    bridge, tmp_path, monkeypatch
):
    """Issue 40: the top axis 2H2 = 2H1/h̄ crowded matplotlib's evenly spaced heights toward
    high h̄ until their labels touched (30 and 35 half a pixel apart). Drawn, no two labels' boxes
    come within half a label's height, each stands over the
    h̄ = 2H1/label it names (H1 from the bridge's file), and they are round numbers."""
    drawn = []
    monkeypatch.setattr(parametric, "save", lambda figure, output: drawn.append(figure) or output)
    h1 = max(load_bridge(BRIDGES / f"{bridge}.yaml").piers.heights) / 2.0  # the tall pier
    for draw in (parametric.plot_onset, parametric.plot_restitution):
        draw(BRIDGES / f"{bridge}.yaml", tmp_path / "x.png")
        figure = drawn.pop()
        canvas = FigureCanvasAgg(figure)
        canvas.draw()  # places the tick labels
        renderer = canvas.get_renderer()
        (axes,) = figure.axes
        (top,) = axes.child_axes
        labels = [t for t in top.get_xticklabels() if t.get_text()]
        low, high = axes.get_xlim()
        shown = [t for t in labels if low <= 2.0 * h1 / float(t.get_text()) <= high]
        assert len(shown) >= 4, [t.get_text() for t in labels]
        boxes = sorted((t.get_window_extent(renderer) for t in shown), key=lambda b: b.x0)
        space = 0.5 * boxes[0].height  # about a character's width: labels that touch collide
        pairs = zip(boxes, boxes[1:], strict=False)
        assert all(a.x1 + space < b.x0 for a, b in pairs), [t.get_text() for t in shown]
        for text in shown:
            value = float(text.get_text())
            assert value == float(f"{value:.1g}") or value == round(value)  # 20, 0.5, 12
            box = text.get_window_extent(renderer)
            x, _ = axes.transData.inverted().transform((0.5 * (box.x0 + box.x1), box.y0))
            assert x == pytest.approx(2.0 * h1 / value, abs=0.05 * (high - low))


def test_parametric_needs_two_piers(tmp_path):
    block = tmp_path / "block.yaml"
    block.write_text("piers: {width: 2.0, heights: [10.0]}\n", encoding="utf-8")
    with pytest.raises(InputError, match="piers.heights: the figure varies a bridge with two"):
        parametric.plot_onset(block, tmp_path / "x.png")


def test_peaks_figure(done, tmp_path):
    with matplotlib.rc_context({"svg.fonttype": "none"}):  # keep the text searchable
        path = plot_peaks(done, tmp_path / "peaks.svg")
    text = svg_text(path)
    for label in ("symmetric (h̄ = 1)", "highly asymmetric (h̄ = 2)", "[mm]", "[mrad]", "R1", "R2"):
        assert label in text, label
    assert "= 120 mm" in text and "= 220 mm" in text  # u_jo and u_jo + u_ab (Fig. 9A)
    for letter in "ABCDE":
        assert f"({letter})" in text


def test_a_peak_of_zero_is_drawn_whole_above_the_frame(done, tmp_path, monkeypatch):
    """Issue 40: a marker at zero (the symmetric bridge's deck never turns) was cut in half by
    the axis; every panel now starts a little below zero."""
    from rockbridge_cli.plots import peaks

    drawn = []
    monkeypatch.setattr(peaks, "save", lambda figure, output: drawn.append(figure) or output)
    plot_peaks(done, tmp_path / "peaks.png")
    panels = [axes for axes in drawn[0].axes if axes.get_ylabel()]
    assert len(panels) == 6
    for axes in panels:
        low, high = axes.get_ylim()
        assert -0.05 * high < low < 0.0 < high


def test_fig_10_has_the_failure_level_and_times_under_every_panel(done, tmp_path, monkeypatch):
    """Issue 40: Fig. 10 lacked the abutment's failure level ±(u_jo + u_ab) that Fig. 9A draws
    (0.12 + 0.10 m = 220 mm for the studied bridges, docs/model.md §2), and only its last panel
    had time labels."""
    from rockbridge_cli.plots import history

    drawn = []
    monkeypatch.setattr(history, "save", lambda figure, output: drawn.append(figure) or output)
    plot_history(done, "R1", tmp_path / "history.png")
    panels = [axes for axes in drawn[0].axes if axes.get_ylabel()]
    deck = next(axes for axes in panels if "u_{deck}" in axes.get_ylabel())
    levels = sorted(
        line.get_ydata()[0]
        for line in deck.get_lines()
        if line.get_linestyle() == "--" and len(set(line.get_ydata())) == 1
    )
    assert levels == pytest.approx([-220.0, 220.0])
    for axes in panels:
        assert all(tick.label1.get_visible() for tick in axes.xaxis.get_major_ticks())


def test_history_figure(done, tmp_path):
    with matplotlib.rc_context({"svg.fonttype": "none"}):
        path = plot_history(done, "R1", tmp_path / "history.svg", bridges=[STUDIED[1]])
    text = svg_text(path)
    assert "highly asymmetric (h̄ = 2)" in text and "symmetric (h̄ = 1)" not in text
    assert "time t [s]" in text and "record R1" in text
    with pytest.raises(InputError, match="no bridge nope"):
        plot_history(done, "R1", tmp_path / "x.png", bridges=["nope"])
    with pytest.raises(InputError, match="unknown figure format '.gif'"):
        plot_history(done, "R1", tmp_path / "x.gif")


def test_peaks_figure_marks_the_means_and_each_bridges_limits(tmp_path, monkeypatch):
    """Bridges with different gaps: each gets its own limit lines (one legend entry per kind),
    each line ending in the markers of the bridges it belongs to (issue 40: they were told
    apart by their shade alone), and each panel ends with the bridges' means over the records.
    The two studied bridges share u_jo = 0.12 m and u_ab = 0.10 m (120 and 220 mm); the third,
    their copy with a 0.06 m gap, has 60 and 160 mm; markers by order, ``o``, ``s``, ``^``."""
    original = (BRIDGES / f"{STUDIED[1]}.yaml").read_text(encoding="utf-8")
    narrow = original.replace("gap: 0.12", "gap: 0.06").replace("highly asymmetric", "narrow gap")
    (tmp_path / "narrow.yaml").write_text(narrow, encoding="utf-8")
    path = write_study(tmp_path, extra="output: {path: out.h5}\n",
                       bridge_files=(tmp_path / "narrow.yaml",))  # fmt: skip
    study = load_study(path)
    run_study(study, workers=1)
    with matplotlib.rc_context({"svg.fonttype": "none"}):
        figure = svg_text(plot_peaks(study.output, tmp_path / "peaks.svg"))
    assert "mean" in figure and "each bridge's: its marker at the right" in figure
    assert "= 120 mm" not in figure  # no single gap is claimed for all bridges
    from rockbridge_cli.plots import peaks

    drawn = []
    monkeypatch.setattr(peaks, "save", lambda figure, output: drawn.append(figure) or output)
    plot_peaks(study.output, tmp_path / "peaks.png")
    deck = drawn[0].axes[0]
    ends = {
        (round(float(line.get_ydata()[0]), 6), line.get_marker())
        for line in deck.lines
        if line.get_transform() != deck.transData and line.get_marker() not in ("None", "")
    }
    assert ends == {(120.0, "o"), (120.0, "s"), (220.0, "o"), (220.0, "s"), (60.0, "^"),
                    (160.0, "^")}  # fmt: skip


@pytest.mark.slow
def test_history_figure_has_the_ground_motion_and_the_events(done, tmp_path):
    """Panel A is the record (in g, from the results file), onsets and poundings are in the
    legend, and the panels follow the five responses of a bridge."""
    with matplotlib.rc_context({"svg.fonttype": "none"}):
        text = svg_text(plot_history(done, "R1", tmp_path / "h.svg"))
    assert "onset of rocking" in text and "pounding on the backwall" in text
    assert all(f"({letter})" in text for letter in "ABCDEF") and "(G)" not in text


def test_history_of_a_single_block_draws_only_what_a_block_has(tmp_path):
    """A free-standing block has no deck and no short pier: ground and θ1 only, not four empty
    panels; a block that overturns gets the failure line and its legend entry."""
    (tmp_path / "block.yaml").write_text(SLENDER_BLOCK, encoding="utf-8")
    path = write_study(tmp_path, bridges=(), extra="output: {path: out.h5}\n",
                       bridge_files=(tmp_path / "block.yaml",))  # fmt: skip
    study = load_study(path)
    run_study(study, workers=1)
    with matplotlib.rc_context({"svg.fonttype": "none"}):
        figure = svg_text(plot_history(study.output, "R1", tmp_path / "block.svg"))
    assert "(A)" in figure and "(B)" in figure and "(C)" not in figure
    assert "tall pier" in figure and "short pier" not in figure
    # `SLENDER_BLOCK` overturns under R1
    assert read_peaks(study.output).set_index("record").loc["R1", "failure_mode"] != "none"
    legend = re.findall(r"<text[^>]*>([^<]*)</text>", figure)
    assert "failure" in legend and "pounding on the backwall" not in legend


@pytest.mark.slow
def test_peaks_figure_of_many_bridges_keeps_its_legend_short(tmp_path):
    """A sweep of 13 gaps: one legend entry says how many bridges, and the 13 pairs of limit
    lines (beyond `MAX_LIMITS`) are left out with a note, instead of 26 lines and 39 entries."""
    path = write_study(tmp_path, bridges=(STUDIED[1],), records=("R1",), extra=(
        "sweep: {fields: {abutments.gap: {start: 0.06, stop: 0.30, count: 13}}}\n"
        "fidelity: fast\noutput: {path: out.h5, histories: none}\n"))  # fmt: skip
    study = load_study(path)
    run_study(study, workers=1)
    with matplotlib.rc_context({"svg.fonttype": "none"}):
        texts = re.findall(r"<text[^>]*>([^<]*)</text>", svg_text(
            plot_peaks(study.output, tmp_path / "many.svg")))  # fmt: skip
    assert any(t.startswith("13 bridges, one marker style each") for t in texts)
    assert "limit lines left out: 13 gaps" in texts
    assert not any(t.startswith(STUDIED[1]) for t in texts)  # no bridge named one by one


@pytest.mark.slow
def test_a_name_with_tex_math_is_drawn_as_written(tmp_path):
    """A bridge named ``$\\undefinedmacro{x$`` broke `plot peaks`, `plot history` and `report`
    (Matplotlib read it as mathematics): names are drawn literally (issue 32)."""
    name = r"cost $5 \undefinedmacro{x$ bridge"
    hostile = tmp_path / "hostile.yaml"
    hostile.write_text((BRIDGES / f"{STUDIED[0]}.yaml").read_text().replace(
        "name: symmetric (h̄ = 1)", f"name: '{name}'"))  # fmt: skip
    path = write_study(tmp_path, bridges=(), records=("R1",), bridge_files=(hostile,),
                       extra="output: {path: out.h5}\n")  # fmt: skip
    study = load_study(path)
    run_study(study, workers=1)
    with matplotlib.rc_context({"svg.fonttype": "none"}):
        peaks = plot_peaks(study.output, tmp_path / "peaks.svg")
        history = plot_history(study.output, "R1", tmp_path / "history.svg")
        onset = parametric.plot_q(hostile, tmp_path / "q.svg")
    for path in (peaks, history, onset):
        assert name in svg_text(path)


def test_a_peaks_figure_of_too_many_bridges_points_to_the_sweeps(tmp_path, monkeypatch):
    """Issue 40: `plot peaks` spent 55 s drawing 1000 bridges; beyond `MAX_BRIDGES` (here 2, of a
    sweep of 3 gaps) it refuses and names `plot sweep`, which draws them."""
    from click.testing import CliRunner

    from rockbridge_cli.cli import main
    from rockbridge_cli.plots import peaks

    monkeypatch.setattr(peaks, "MAX_BRIDGES", 2)
    path = write_study(tmp_path, bridges=(STUDIED[1],), records=("R1",), extra=(
        "sweep: {fields: {abutments.gap: {start: 0.06, stop: 0.30, count: 3}}}\n"
        "fidelity: fast\noutput: {path: out.h5, histories: none}\n"))  # fmt: skip
    study = load_study(path)
    run_study(study, workers=1)
    refused = CliRunner().invoke(main, ["plot", "peaks", str(study.output)])
    assert refused.exit_code == 2
    command = f"rockbridge plot sweep {study.output} --field abutments.gap"
    assert refused.output.strip().endswith(command)
    drawn = CliRunner().invoke(main, [*command.split()[1:], "-o", str(tmp_path / "sweep.png")])
    assert drawn.exit_code == 0, drawn.output


def test_a_sweeps_legend_stands_beside_its_curves_and_names_the_bridge_once(tmp_path):
    """Issue 40: `plot sweep`'s legend (loc="best", over the curves; matplotlib warned on the
    terminal that "best" is slow with much data) now stands beside the axes, the one bridge
    named once as its title. A grid of 3 gaps × 3 heights: three curves against the gap."""
    import warnings

    from rockbridge_cli.plots.sweep import plot_sweep

    path = write_study(tmp_path, bridges=(STUDIED[0],), records=("R1",), extra=(
        "sweep: {fields: {abutments.gap: {start: 0.06, stop: 0.18, count: 3}, piers.heights.1: "
        "{start: 13.0, stop: 26.0, count: 3}}, grid: true}\n"
        "fidelity: fast\noutput: {path: out.h5, histories: none}\n"))  # fmt: skip
    study = load_study(path)
    run_study(study, workers=1)
    with warnings.catch_warnings(), matplotlib.rc_context({"svg.fonttype": "none"}):
        warnings.simplefilter("error")
        texts = re.findall(r"<text[^>]*>([^<]*)</text>", svg_text(
            plot_sweep(study.output, tmp_path / "sweep.svg", "abutments.gap")))  # fmt: skip
    assert texts.count(STUDIED[0]) == 1
    assert [t for t in texts if t.startswith("piers.heights.1 = ")] == [
        "piers.heights.1 = 13",
        "piers.heights.1 = 19.5",
        "piers.heights.1 = 26",
    ]


def test_the_fragility_figure_does_not_load_scipy_stats():
    """Issue 40: `plot fragility` took 12–18 s; importing scipy.stats for the normal CDF was a
    fifth of the command's CPU time (4.9 s → 3.9 s on paper-ida without it). The CDF is
    scipy.special's ``ndtr``; nothing on the figure's path loads scipy.stats."""
    code = (
        "import sys\n"
        "from rockbridge_cli.cli import fragility\n"
        "from rockbridge_cli.plots.fragility import plot_fragility\n"
        "print('scipy.stats' in sys.modules)\n"
    )
    assert fresh_python(code) == "False"


def test_a_sweep_along_a_continuous_second_field_is_a_grey_ramp(tmp_path, monkeypatch):
    """Issue 40: a grid's second field gave a legend entry per value (20 over the curves).
    Beyond `RAMP_LINES` values (here 8 heights), the lines are greys from light (the lowest
    height) to black (the highest), named by a colour bar of the field, with no legend."""
    from matplotlib.colors import to_rgb

    from rockbridge_cli.plots import sweep

    path = write_study(tmp_path, bridges=(STUDIED[0],), records=("R1",), extra=(
        "sweep: {fields: {abutments.gap: {start: 0.06, stop: 0.18, count: 2}, piers.heights.1: "
        "{start: 13.0, stop: 26.0, count: 8}}, grid: true}\n"
        "fidelity: fast\noutput: {path: out.h5, histories: none}\n"))  # fmt: skip
    study = load_study(path)
    run_study(study, workers=1)
    drawn = []
    monkeypatch.setattr(sweep, "save", lambda figure, output: drawn.append(figure) or output)
    sweep.plot_sweep(study.output, tmp_path / "sweep.png", "abutments.gap")
    axes, bar = drawn[0].axes
    assert not drawn[0].legends and bar.get_ylabel() == "piers.heights.1 [m]"
    assert bar.get_ylim() == (13.0, 26.0)
    greys = [to_rgb(line.get_color()) for line in axes.lines]
    assert len(greys) == 8 and all(r == g == b for r, g, b in greys)
    assert greys[0][0] == pytest.approx(0.78, abs=0.01) and greys[-1] == (0.0, 0.0, 0.0)
    assert [g[0] for g in greys] == sorted((g[0] for g in greys), reverse=True)
    assert axes.get_title().startswith(STUDIED[0])
