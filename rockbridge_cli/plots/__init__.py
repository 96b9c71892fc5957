"""Figures: the paper's (`peaks`: Fig. 9, `history`: Fig. 10, `parametric`: Figs. 3–8), the
spectra of record sets, IDA curves, sweeps and fragility curves; `common` holds the shared style."""
