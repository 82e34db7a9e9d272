"""Reporting: the verdicts on the paper's claims (steady state and shear rotation), the figures,
the report's tables, the map over state points and the comparison of datasets.

The highest stage: it may import every other.
"""
