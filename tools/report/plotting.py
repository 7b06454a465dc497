"""Matplotlib set-up shared by every report figure: no display, a fixed style, deterministic PNG and SVG
(no dates or random ids in the files, so the same inputs give byte-identical figures)."""
import os

import matplotlib

matplotlib.use("Agg")
matplotlib.rcParams.update({"svg.hashsalt": "synsculpt", "font.size": 9, "axes.spines.top": False,
                            "axes.spines.right": False, "figure.dpi": 100})
import matplotlib.pyplot as pyplot  # noqa: E402  (after the backend is chosen)


def new_figure(width, height, rows=1, columns=1, **kwargs):
    return pyplot.subplots(rows, columns, figsize=(width, height), **kwargs)


def save(figure, stem):
    """Writes STEM.png and STEM.svg, each through a temporary name and a rename."""
    os.makedirs(os.path.dirname(stem) or ".", exist_ok=True)
    figure.tight_layout()
    for extension, metadata in (("png", {"Software": None}), ("svg", {"Date": None, "Creator": None})):
        temporary = f"{stem}.tmp-{os.getpid()}.{extension}"
        figure.savefig(temporary, format=extension, dpi=110, metadata=metadata)
        os.replace(temporary, f"{stem}.{extension}")
    pyplot.close(figure)
