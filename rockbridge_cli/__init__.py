"""rockbridge: seismic response of bridges on rocking piers of unequal height.

The mechanics follow Thomaidis, Camara & Kappos (2022), *Dynamics and seismic performance of
asymmetric rocking bridges*, J. Eng. Mech. 148(3) 04022003, as corrected in the project's
docs/model.md.

The package's rooms, from the ground up (docs/architecture.md): `core` (the mechanics and the
integrator), `errors`, `cpus` and `interrupts` beside it; `motions` (ground-motion numerics),
`paths` (reading and writing files safely) and `kinds` (which kind of file a path holds);
`records` (record files and sets) and `warmup` (compiling every kernel once); `results` (the HDF5
file); `config` (YAML → pydantic); `assessment` (what is computed from a results file); `study`
(running a study) and `plots`; `report`; `cli` (the command line).
"""

__version__ = "0.1.0"
