"""The bridge's mechanics: the model (`geometry`, `kinematics`, `dynamics`, `impacts`), the
devices a pier may carry (`devices`, their mechanics `device_mechanics`, the events of the
yielding ones `device_events` and their histories `device_histories`), one
bridge as analyzed (`bridge`) and its summary (`summary`), the event-driven integrator (`solver`,
`schemes`, `tables`, its event location `events`, `analysis`; many analyses of a bridge in one
compiled call, `batch`) at a fidelity (`fidelity`), a cache bounded by its bytes (`memo`) and the
vocabulary of what an analysis reports (`quantities`). It imports only numpy, scipy and numba
(with its llvmlite), and nothing else of the package; `_jit` is where every compiled kernel of
the package, here and in `motions`, chooses its compiler."""
