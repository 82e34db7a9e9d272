"""Every figure the docs show can be read where it is shown: its smallest text (tick labels, legends,
axis labels, titles) has digits and capitals at least 10 px tall at the width the page gives it, the
image's own width or the text column's 868 px at a 1400 px window, whichever is smaller. Digits and
capitals of DejaVu Sans (matplotlib's font) are 0.729 of the font size: a 10 px digit needs a 13.7 px
font. Sub- and superscripts of mathtext are drawn smaller and are not counted.

``save_figure`` writes the smallest font it drew, in image px, into the PNG (a text chunk); the test
reads it with the image's width, so it needs no rebuild. A PNG without the chunk was not saved by
``save_figure`` and fails.
"""

from pathlib import Path

import matplotlib.pyplot as plt
import pytest
from PIL import Image

from suspension_fabric.reporting.figures import (
    DOCS_COLUMN_PX,
    SMALLEST_FONT_KEY,
    displayed_font_px,
    save_figure,
    smallest_font_pt,
)

REPO = Path(__file__).resolve().parents[2]
FIGURES = sorted((REPO / "docs" / "figures").glob("*.png"))
#: the smallest legible height of a digit as displayed, CSS px
MIN_DIGIT_PX = 10.0
#: height of a digit or capital of DejaVu Sans over the font size
DIGIT_HEIGHT = 0.729


def displayed_smallest_px(path: Path) -> float:
    """The smallest font of a saved PNG as the docs show it (CSS px)."""
    with Image.open(path) as image:
        width = image.width
        recorded = image.info.get(SMALLEST_FONT_KEY)
    if recorded is None:
        pytest.fail(f"{path.name}: no '{SMALLEST_FONT_KEY}' text chunk: not saved by figures.save_figure")
    return float(recorded) * min(width, DOCS_COLUMN_PX) / width


def test_the_docs_have_figures():
    assert len(FIGURES) >= 20


@pytest.mark.parametrize("path", FIGURES, ids=[path.name for path in FIGURES])
def test_smallest_text_is_legible_as_displayed(path):
    digit = DIGIT_HEIGHT * displayed_smallest_px(path)
    assert digit >= MIN_DIGIT_PX, f"{path.name}: smallest digits {digit:.1f} px tall at the docs' width"


def test_save_figure_records_the_smallest_font_drawn(tmp_path):
    """The chunk holds the smallest visible text in image px (200 dpi): a 7 pt legend in a figure of
    10 pt ticks is 7 * 200 / 72 px; the text of a hidden panel does not count."""
    fig, (ax, hidden) = plt.subplots(1, 2, figsize=(8, 3))
    ax.plot([0, 1], [0, 1], label="line")
    ax.legend(fontsize=7)
    hidden.set_title("tiny", fontsize=3)
    hidden.set_visible(False)
    assert smallest_font_pt(fig) == 7
    _, png = save_figure(fig, tmp_path / "figure")
    with Image.open(png) as image:
        assert float(image.info[SMALLEST_FONT_KEY]) == pytest.approx(7 * 200 / 72, abs=0.01)
        assert image.width == 1600
    # shown 868 px wide: 7 pt at 8 in is 7 * 868 / (72 * 8) = 10.5 px
    assert displayed_font_px(7, 8) == pytest.approx(7 * 868 / (72 * 8))
    assert displayed_font_px(7, 3) == pytest.approx(7 * 200 / 72)  # narrower than the column: its own size
