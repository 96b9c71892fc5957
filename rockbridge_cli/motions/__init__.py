"""Ground-motion numerics, on arrays and in SI units: EN 1998-1 elastic spectra (`ec8`), linear
response spectra (`spectra`) and the fit to a target between any two periods (`spectral_fit`),
spectral matching (`matching`, `wavelets`, of recorded seeds `seeds`), the selection and scaling
of recorded motions (`selection`), two horizontal components combined (`orientation`: the
component along any axis, RotD50 and RotD100), baseline correction and durations (`baseline`),
intensity measures (`intensity`), velocity pulses in records (`pulse_identification`) and
analytic pulses (`pulses`). Like `core`, it reads no file and imports only numpy, scipy and numba
(and from the core its compiler, `core._jit`, and its vocabulary, `core.quantities`); record
files and sets are `records`'."""
