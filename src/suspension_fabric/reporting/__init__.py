"""Reporting: the figures and the report's HTML pages (one module per page), the map figures, the
protocols' figures and results fragment, and the fragments the docs and the README quote, from what
[`suspension_fabric.evaluation`][suspension_fabric.evaluation] computes.

The highest stage: it may import every other.
"""
