"""Mechanics layer of the loaded tooth contact analysis (issue 13).

Self-contained and geometry-free: numpy/scipy only, units mm, N, MPa (N/mm^2).

- :mod:`~beveloid.loaded.halfspace`: Boussinesq/Love influence coefficients of rectangular
  cells on an elastic half-space, combined modulus of two bodies;
- :mod:`~beveloid.loaded.lcp`: normal contact with a rigid approach and a weighted load
  constraint (active-set solver);
- :mod:`~beveloid.loaded.hertz`: Hertz elliptical point contact and line contact;
- :mod:`~beveloid.loaded.tooth_compliance`: thin-slice tooth bending/shear/foundation
  compliance with a face-wise coupling, as influence coefficients.

The model, every choice and its limits: ``docs/loaded_contact.md``.
"""
