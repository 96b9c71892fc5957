"""rockbridge: seismic response of bridges on rocking piers of unequal height.

The mechanics follow Thomaidis, Camara & Kappos (2022), *Dynamics and seismic performance of
asymmetric rocking bridges*, J. Eng. Mech. 148(3) 04022003, as corrected in the project's
docs/model.md.
"""

__version__ = "0.1.0"
