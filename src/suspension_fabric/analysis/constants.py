"""Physical constants the stress reading and the engine share (a module of its own, importing
nothing, so that the simulations' code versions do not follow the analysis code)."""

__all__ = ["EINSTEIN_COEFFICIENT"]

#: The Einstein coefficient: force- and torque-free spheres add 2.5 phi to the relative viscosity
#: (A. Einstein, "Berichtigung zu meiner Arbeit: Eine neue Bestimmung der Moleküldimensionen",
#: Ann. Phys. 34, 591-592, 1911, which corrects the 1 phi of Ann. Phys. 19, 289, 1906), a stress no
#: force of the simulation carries.
EINSTEIN_COEFFICIENT = 2.5
