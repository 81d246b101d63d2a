"""Content checks for the PNG figures the package writes.

A PNG signature only says a file was written; these checks say something was
drawn: the image has a sensible size, is not blank (enough pixels differ from
the background), and, for figures meant for a page, is not wider than a page
at the saved resolution.
"""
from pathlib import Path

import numpy as np

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"
# Page width: a figure up to ~10 inches at the package's 100 dpi.
PAGE_WIDTH_PX = 1000


def read_png(path) -> np.ndarray:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.image as mpimg
    data = Path(path).read_bytes()
    assert data[:8] == PNG_SIGNATURE, f"{path} is not a PNG"
    return mpimg.imread(str(path))


def drawn_fraction(image: np.ndarray) -> float:
    """Fraction of pixels that differ from the most common colour (the
    background) by more than 2 % in any channel."""
    rgb = image[..., :3].reshape(-1, 3)
    values, counts = np.unique(np.round(rgb, 2), axis=0, return_counts=True)
    background = values[np.argmax(counts)]
    return float(np.mean(np.any(np.abs(rgb - background) > 0.02, axis=1)))


def assert_figure(path, min_drawn: float = 0.01, page_width: bool = False,
                  min_width: int = 200, min_height: int = 150) -> np.ndarray:
    """The PNG at `path` has at least min_width x min_height pixels, at least
    `min_drawn` of its pixels drawn, and (page_width) fits a page's width.
    Returns the image for further checks."""
    image = read_png(path)
    height, width = image.shape[:2]
    assert width >= min_width and height >= min_height, (path, width, height)
    if page_width:
        assert width <= PAGE_WIDTH_PX, f"{path}: {width} px wide, more than a page ({PAGE_WIDTH_PX} px)"
    drawn = drawn_fraction(image)
    assert drawn >= min_drawn, f"{path}: only {drawn:.4f} of the pixels are drawn (blank figure?)"
    return image
