"""The numerical core: the model (`geometry`, `kinematics`, `dynamics`, `impacts`), one bridge as
analysed (`bridge`), the event-driven integrator (`solver`, `schemes`, `analysis`) and the
ground-motion numerics (`spectra`, `ec8`, `matching`, `wavelets`, `baseline`). It imports only
numpy, scipy and numba."""
