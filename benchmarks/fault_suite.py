"""Run the fault suite (the tests marked `fault`) and count its cases by outcome and result.

    .venv/bin/python benchmarks/fault_suite.py            # Markdown tables for BENCHMARKS.md

Each case is one collected test (a parametrized test counts once per parameter set; a
property-based test once, whatever number of examples it draws). The outcomes are those of
tests/conftest.py (FAULT_OUTCOMES): how the case ends, which the test asserts.
"""

from __future__ import annotations

import collections
import sys
import time
from pathlib import Path

import pytest

TESTS = Path(__file__).resolve().parents[1] / "tests"


class Tally:
    """A pytest plugin: the outcome marker and the result of every case that runs."""

    def __init__(self):
        self.outcome = {}
        self.result = {}

    def pytest_collection_modifyitems(self, items):
        for item in items:
            mark = item.get_closest_marker("fault")
            if mark is not None:
                self.outcome[item.nodeid] = mark.args[0]

    def pytest_runtest_logreport(self, report):
        if report.nodeid not in self.outcome:
            return
        if self.result.get(report.nodeid) == "failed":
            return
        if report.failed:
            self.result[report.nodeid] = "failed"
        elif report.skipped:
            self.result[report.nodeid] = "skipped"
        elif report.when == "call":
            self.result[report.nodeid] = "passed"


def tables(tally: Tally) -> str:
    sys.path.insert(0, str(TESTS))
    from conftest import FAULT_OUTCOMES

    results = ("passed", "failed", "skipped", "not run")
    counts = collections.Counter((tally.outcome[node], tally.result.get(node, "not run")) for node in tally.outcome)
    header = "| outcome | what the case asserts | cases | " + " | ".join(results) + " |"
    lines = [header, "|---|---|---|" + "---|" * len(results)]
    for outcome, meaning in [*FAULT_OUTCOMES.items(), ("all", "")]:
        row = [sum(n for (o, r), n in counts.items() if r == result and outcome in (o, "all")) for result in results]
        lines.append(f"| {outcome} | {meaning} | {sum(row)} | " + " | ".join(map(str, row)) + " |")
    by_file = collections.Counter(node.split("::")[0] for node in tally.outcome)
    lines += ["", "| file | cases |", "|---|---|"] + [f"| `{name}` | {n} |" for name, n in sorted(by_file.items())]
    return "\n".join(lines)


def main() -> int:
    tally = Tally()
    start = time.perf_counter()
    # in this process (-n0): pytest-xdist's workers would report to a controller that collects nothing
    code = pytest.main(["-m", "fault", "-q", "-n0", "-p", "no:cacheprovider", str(TESTS)], plugins=[tally])
    print(f"\nfault suite: {time.perf_counter() - start:.0f} s, pytest exit code {int(code)}\n")
    print(tables(tally))
    return int(code)


if __name__ == "__main__":
    raise SystemExit(main())
