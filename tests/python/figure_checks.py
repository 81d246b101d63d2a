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
    rounded = np.round(rgb, 2)
    # The most common rounded colour, the lexicographically smallest of equally
    # common ones (as np.unique(axis=0) would order them), counted through one
    # integer per colour: each channel is a whole number of hundredths (0..100),
    # so r 101^2 + g 101 + b orders the colours as the rows.  np.unique over
    # rows took up to 0.8 s per figure.
    hundredths = np.rint(rounded * 100).astype(np.int64)
    if hundredths.min() < 0 or hundredths.max() > 100:
        raise ValueError("drawn_fraction: channels outside [0, 1]")
    key = (hundredths[:, 0] * 101 + hundredths[:, 1]) * 101 + hundredths[:, 2]
    background = rounded[np.argmax(key == np.argmax(np.bincount(key)))]
    return float(np.mean(np.any(np.abs(rgb - background) > 0.02, axis=1)))


def distinct_colours(image: np.ndarray) -> int:
    """The number of distinct pixel values (all channels) of an image read from
    a PNG: len(np.unique(pixels, axis=0)) through one byte string per pixel,
    about 8x faster."""
    pixels = np.ascontiguousarray(image.reshape(-1, image.shape[-1]))
    return len(np.unique(pixels.view(np.dtype((np.void, pixels.dtype.itemsize * pixels.shape[1]))).ravel()))


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
