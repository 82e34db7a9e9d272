"""Reporting: the figures and the report's HTML pages (one module per page), the map figures, and
the protocols' figures and results fragment, from what [`suspension_fabric.evaluation`][suspension_fabric.evaluation]
computes.

The highest stage: it may import every other.
"""
