"""Names of the fabric's measured quantities, apart from their measurement: the six components of
<nn> and the 15 of <nnnn> as the fabric tables' columns, the spherical-harmonic amplitudes'
columns, the near-contact threshold's default, and display labels.

They live apart from [`suspension_fabric.analysis.fabric`][suspension_fabric.analysis.fabric]
(which re-exports them) so that the many workflow jobs that read fabric tables, but detect no
contacts, start without importing MDAnalysis.
"""

from __future__ import annotations

__all__ = [
    "DEFAULT_EPS",
    "COMPONENTS",
    "component_label",
    "FOURTH_MOMENT_COMPONENTS",
    "HARMONIC_ORDERS",
    "HARMONIC_COLUMNS",
]

#: Near-contact gap threshold as a fraction of the smaller diameter of the pair (paper).
DEFAULT_EPS = 0.01

#: Names of the six independent fabric components (the column names of the fabric tables)
#: and their (row, column) indices.
COMPONENTS: dict[str, tuple[int, int]] = {
    "n11": (0, 0),
    "n22": (1, 1),
    "n33": (2, 2),
    "n12": (0, 1),
    "n13": (0, 2),
    "n23": (1, 2),
}
_SUBSCRIPT = str.maketrans("0123456789", "₀₁₂₃₄₅₆₇₈₉")


def component_label(name: str) -> str:
    """Display name of a fabric component or quantity: "n12" -> "⟨nn⟩₁₂", "Z" -> "Z"."""
    if name in COMPONENTS:
        return f"⟨nn⟩{name[1:].translate(_SUBSCRIPT)}"
    return name


#: The 15 independent components of the fully symmetric <nnnn> (i <= j <= k <= l), named as the
#: fabric table's columns, with their (i, j, k, l) indices.
FOURTH_MOMENT_COMPONENTS: dict[str, tuple[int, int, int, int]] = {
    f"n{i + 1}{j + 1}{k + 1}{l + 1}": (i, j, k, l)
    for i in range(3)
    for j in range(i, 3)
    for k in range(j, 3)
    for l in range(k, 3)  # noqa: E741 (the index's name in the formula)
}
#: Orders of the spherical-harmonic amplitudes recorded (the odd ones vanish: a pair has no sign).
HARMONIC_ORDERS: tuple[int, ...] = (0, 2, 4, 6)


def _harmonic_name(l: int, m: int) -> str:  # noqa: E741
    return f"Y{l}_{'m' if m < 0 else 'p' if m > 0 else ''}{abs(m)}"


#: Columns of the spherical-harmonic amplitudes a_lm, l in HARMONIC_ORDERS, m = -l ... l.
HARMONIC_COLUMNS: tuple[str, ...] = tuple(_harmonic_name(l, m) for l in HARMONIC_ORDERS for m in range(-l, l + 1))
