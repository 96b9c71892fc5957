"""Figures: the paper's (`peaks`: Fig. 9, `history`: Fig. 10, `parametric`: Figs. 3–8), the spectra
(`spectra`) and histories (`motion`) of records, a selected set's spectra (`selection`), IDA curves
(`ida`), sweeps (`sweep`), fragility curves (`fragility`), sensitivity indices and tornadoes
(`sensitivity`) and overturning spectra (`overturning`); `common` holds the shared style."""
