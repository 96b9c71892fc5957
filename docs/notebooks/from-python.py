# ---
# jupyter:
#   jupytext:
#     formats: py:percent
#     text_representation:
#       extension: .py
#       format_name: percent
# ---

# %% [markdown]
# # rockbridge from Python
#
# README's "From Python" path, worked: load a bridge, analyse it under a record, run a small
# study of stripes, read its peak table with pandas, fit the fragilities and draw a figure.
#
# This file is a notebook in jupytext's "percent" form (`# %%` starts a cell), kept as a plain
# script so that a change to it reads as a diff. It runs as it is, without Jupyter:
#
#     cd "$(mktemp -d)" && python /path/to/rockbridge/docs/notebooks/from-python.py
#
# and the test suite runs it so (`tests/test_notebook.py`). To open it in Jupyter, convert it
# with jupytext (not one of rockbridge's dependencies: `pip install jupytext`):
#
#     jupytext --to ipynb docs/notebooks/from-python.py      # → from-python.ipynb beside it
#
# It writes its files (a study, its results file, the figure `from-python.png`) into the
# current folder; started inside the repository (Jupyter opens a notebook in its own folder),
# it moves to a new temporary folder first, so that the repository stays as it was.
# About 10 s on two idle cores (more on a loaded one), most of it imports and starting workers.

# %%
import os
import tempfile
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
from scipy.stats import norm

from rockbridge_cli.assessment.fragility import fragilities
from rockbridge_cli.config.bridge import load_bridge
from rockbridge_cli.config.study import load_study
from rockbridge_cli.core.analysis import analyze
from rockbridge_cli.records.files import read_record
from rockbridge_cli.results import read_peaks
from rockbridge_cli.study.run import run_study

# The repository: this file's grandparent, or (in Jupyter, which has no __file__) the nearest
# folder above the working one that holds the bundled bridges.
HERE = Path(__file__).resolve().parent if "__file__" in globals() else Path.cwd().resolve()
REPO = next(p for p in (HERE, *HERE.parents) if (p / "configs" / "bridges").is_dir())
if Path.cwd().resolve().is_relative_to(REPO):
    os.chdir(tempfile.mkdtemp(prefix="rockbridge-notebook-"))
print("repository:", REPO)
print("writing into:", Path.cwd())

# %% [markdown]
# ## A bridge
#
# `load_bridge` reads and validates a bridge file (every error names the file, the field and
# the reason). The highly asymmetric studied bridge of the paper, h̄ = 2 (Table 1):

# %%
bridge = load_bridge(REPO / "configs" / "bridges" / "studied-hbar2.00.yaml")
print(bridge.name)

# %% [markdown]
# ## One analysis
#
# A record is read in SI (m/s², s), whatever units its file states. `analyze` takes the bridge
# *as analyzed*, `to_bridge()`: the core model (tall pier first) with the side of the tall pier
# and the restitution the file may give. The peaks are (value, time) pairs in SI; the
# demand/capacity ratio of the backfill is the paper's.

# %%
record = read_record(REPO / "records" / "ec8-type1-C-ag0.6g" / "AR06.txt")
response = analyze(bridge.to_bridge(), record.acceleration, record.time_step)
u_deck, t_peak = response.peaks["u_deck"]
print(f"peak deck displacement {u_deck:.4f} m at {t_peak:.2f} s")
print(f"backfill demand/capacity {response.dcr_backfill:.3f}; failure: {response.failure_mode}")

# %% [markdown]
# ## A small study: stripes of scaled records
#
# A study is a YAML file: bridges × records (× intensity levels), the fidelity and the output.
# This one takes the symmetric and the highly asymmetric bridge under the ten bundled records,
# each scaled to seven peak ground accelerations (multiple-stripe analysis, 140 analyses), at
# the `fast` fidelity and keeping no histories. Its paths are absolute and point into the
# repository, outside the study's own folder: a study may reach files elsewhere only where
# `ROCKBRIDGE_PATHS` names them (docs/studies.md, "Paths in configs").

# %%
os.environ["ROCKBRIDGE_PATHS"] = str(REPO)
bridges = [REPO / "configs" / "bridges" / f"studied-hbar{h}.yaml" for h in ("1.00", "2.00")]
study_file = Path("stripes.yaml")
study_file.write_text(
    f"""\
description: two studied bridges under the ten bundled records, PGA 0.1-1.5 g
bridges: [{", ".join(str(b) for b in bridges)}]
records: {{set: {REPO / "records" / "ec8-type1-C-ag0.6g"}}}
intensity:
  measure: pga_g
  design: 0.69
  levels: [0.1, 0.3, 0.5, 0.7, 0.9, 1.1, 1.5]
fidelity: fast
output: {{path: results/stripes.h5, histories: none}}
""",
    encoding="utf-8",
)
report = run_study(load_study(study_file))
print(f"{report.ran} analyses in {report.wall_time_s:.1f} s on {report.workers} workers")
print("statuses:", report.statuses, "→", report.output)

# %% [markdown]
# ## The peak table, with pandas
#
# `read_peaks` gives one row per analysis (bridge × scaled record), SI values, and the units in
# `peaks.attrs["units"]`; a study with stripes adds `base_record`, `intensity` and `scale`.
# The median demand/capacity ratio of the backfill at each level:

# %%
peaks = read_peaks(report.output)
units = peaks.attrs["units"]
print(f"{len(peaks)} rows; u_deck_max [{units['u_deck_max']}], t_onset [{units['t_onset']}]")
print(peaks[["bridge", "record", "intensity", "u_deck_max", "dcr_backfill", "status"]].head())
table = peaks.groupby(["intensity", "bridge"])["dcr_backfill"].median().unstack("bridge")
print(table.round(3))

# %% [markdown]
# ## Fragilities
#
# `fragilities` fits, per bridge and limit state, a lognormal fragility by maximum likelihood
# on the counts of each stripe (median θ and log-standard deviation β), with a 90 % bootstrap
# interval of the median over the records. Where the levels do not resolve β it is left None
# (and the median is the level, or the geometric mean of two levels, that separates the
# records); a state no record reaches has no median.

# %%
fits = fragilities(report.output)
summary = pd.DataFrame(
    [(f.bridge, f.limit_state, f.median, f.beta, f.median_90) for f in fits],
    columns=["bridge", "limit state", "median [g]", "beta", "median 5-95 %"],
)
print(summary.to_string(index=False))

# %% [markdown]
# ## A figure
#
# Left: the deck's displacement under AR06 (the analysis above). Right: the share of records
# reaching half the backfill's capacity at each level, and the fitted curves
# P = Φ(ln(im/θ)/β).

# %%
fig, (left, right) = plt.subplots(1, 2, figsize=(10, 4), layout="constrained")
left.plot(response.time, response.histories["u_deck"], lw=0.8)
left.set(xlabel="time [s]", ylabel="u_deck [m]", title=f"{bridge.name} under {record.name}")
im = np.linspace(0.05, 2.0, 200)
for fit in (f for f in fits if f.limit_state == "backfill_50"):
    (points,) = right.plot(fit.levels, fit.fractions, "o", label=f"{fit.bridge}, stripes")
    if fit.median is not None and fit.beta is not None:
        right.plot(im, norm.cdf(np.log(im / fit.median) / fit.beta), color=points.get_color(),
                   label=f"θ = {fit.median:.2f} g, β = {fit.beta:.2f}")  # fmt: skip
right.set(xlabel="PGA [g]", ylabel="P(backfill at 50 % of capacity)", ylim=(-0.02, 1.02))
right.legend(fontsize="small")
figure = Path("from-python.png")
fig.savefig(figure, dpi=100)
print("figure:", figure.resolve())
