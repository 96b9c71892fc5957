"""Ground-motion numerics, on arrays and in SI units: EN 1998-1 elastic spectra (`ec8`), linear
response spectra (`spectra`), spectral matching (`matching`, `wavelets`) and baseline correction
(`baseline`). Like `core`, it reads no file and imports only numpy, scipy and numba (its kernels
take their compiler from `core._jit`); record files and sets are `records`'."""
