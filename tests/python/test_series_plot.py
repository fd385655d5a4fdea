"""The series plot (validation/harness/plot_series.py) is laid out by hand for speed (fixed margins, no
tight_layout, no mathtext): it must still draw every panel, with the densities below atol_k masked and the
unresolved region shaded."""
import csv
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

HARNESS = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "validation", "harness")
sys.path.insert(0, HARNESS)
import plot_series  # noqa: E402


def write(path, header, rows):
    with open(path, "w", newline="") as handle:
        writer = csv.writer(handle)
        writer.writerow(header)
        writer.writerows(rows)


def test_every_panel_masks_and_shading(tmp_path, monkeypatch):
    series, distribution, png = tmp_path / "series.csv", tmp_path / "distribution.csv", tmp_path / "report.png"
    times = [1.0 + i for i in range(20)]
    write(series, ["t", "M0", "M2", "M3", "mass_leak"],
          [[t, 1 / (1 + t), 1 + 2 * t, 1 + 6 * t + 6 * t * t, 0.0] for t in times])
    # n_k = 2^-k at t = 1 and 10: sizes with n_k below atol_k = max(1e-8 k^-3, 1e-16) must not be drawn.
    write(distribution, ["t", "k", "n", "cdf"], [[t, k, 2.0 ** -k, 0.0] for t in (1.0, 10.0) for k in range(1, 101)])
    figures = []
    original = plt.subplots

    def keep(*args, **kwargs):
        figure, grid = original(*args, **kwargs)
        figures.append(figure)
        return figure, grid

    monkeypatch.setattr(plot_series.plt, "subplots", keep)
    monkeypatch.setattr(sys, "argv", ["plot_series.py", "--output", str(png), "--title=test", "--series", "cvode",
                                      str(series), "--distribution", "cvode", str(distribution),
                                      "--absolute-tolerance", "cvode", "1e-8", "3", "1e-16"])
    assert plot_series.main() == 0
    assert png.stat().st_size > 10000 and png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    visible = [axes for axes in figures[0].axes if axes.get_visible()]
    assert [axes.get_title() for axes in visible] == ["M0", "M2", "M3", "mass_leak", "size distribution"]
    for axes in visible[:4]:
        assert len(axes.get_lines()) == 1 and len(axes.get_lines()[0].get_xdata()) == len(times)
    sizes = visible[4]
    lines = sizes.get_lines()
    assert len(lines) == 2  # t = 1 and t = 10
    for line in lines:  # only resolved densities: n_k = 2^-k ≥ atol_k
        for k, n in zip(line.get_xdata(), line.get_ydata()):
            assert n >= max(1e-8 * k ** -3, 1e-16)
        last = max(line.get_xdata())
        assert 2.0 ** -(last + 1) < max(1e-8 * (last + 1) ** -3, 1e-16)  # the next size is masked
    assert len(sizes.collections) == 1  # the shaded region below atol_k
    # Log axes carry decade labels in plain text (no mathtext): '10⁻⁵'.
    assert plot_series.decade_label(1e-5) == "10\u207b\u2075" and plot_series.decade_label(3.0) == ""
    # The panels do not overlap: fixed margins leave every axes inside the figure, apart from the others.
    boxes = [axes.get_position() for axes in visible]
    for i, a in enumerate(boxes):
        assert 0 < a.x0 < a.x1 < 1 and 0 < a.y0 < a.y1 < 1
        for b in boxes[i + 1:]:
            assert a.x1 <= b.x0 or b.x1 <= a.x0 or a.y1 <= b.y0 or b.y1 <= a.y0
    assert not any(math.isnan(v) for box in boxes for v in (box.x0, box.y0))
