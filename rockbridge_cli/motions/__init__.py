"""Ground-motion numerics, on arrays and in SI units: EN 1998-1 elastic spectra (`ec8`), linear
response spectra (`spectra`), spectral matching (`matching`, `wavelets`), baseline correction
(`baseline`), intensity measures (`intensity`) and velocity pulses in records
(`pulse_identification`). Like `core`, it reads no file and imports only numpy, scipy and numba
(and from the core its compiler, `core._jit`, and its vocabulary, `core.quantities`); record
files and sets are `records`'."""
