"""Reporting: the verdicts on the paper's claims (steady state and shear rotation), the figures,
the report's tables, the map over state points, the comparison of datasets, and the protocols'
figures and results fragment.

The highest stage: it may import every other.
"""
