#!/usr/bin/env python3
"""Draws a particle configuration as discs coloured by cluster. Called by
validation/io/particle_snapshot.cpp:

  plot_clusters.py --points points.csv --output picture.png --radius R --dimension 2|3 [--box LX LY]

points.csv has the header x,y,z,cluster. In 3-D the particles are projected on the x-y plane, drawn from
low to high z. With --box (periodic), discs crossing a wall are also drawn at their periodic images. Clusters get golden-ratio hues, so neighbouring labels differ; single particles are grey.
"""
import argparse
import colorsys
import sys
import warnings

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import EllipseCollection  # noqa: E402


def colours(labels):
    sizes = np.bincount(labels)
    hue = (labels * 0.6180339887498949) % 1.0
    rgb = np.array([colorsys.hsv_to_rgb(h, 0.75, 0.9) for h in hue]) if len(labels) else np.zeros((0, 3))
    rgb[sizes[labels] == 1] = (0.7, 0.7, 0.7)
    return rgb


def with_periodic_images(x, y, rgb, radius, box):
    """Adds the images (shifted by ±L) of the discs that cross a wall, so they show whole on both sides."""
    xs, ys, cs = [x], [y], [rgb]
    for sx in (-box[0], 0.0, box[0]):
        for sy in (-box[1], 0.0, box[1]):
            if sx == 0.0 and sy == 0.0:
                continue
            inside = ((x + sx > -radius) & (x + sx < box[0] + radius) &
                      (y + sy > -radius) & (y + sy < box[1] + radius))
            xs.append(x[inside] + sx)
            ys.append(y[inside] + sy)
            cs.append(rgb[inside])
    return np.concatenate(xs), np.concatenate(ys), np.concatenate(cs)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--points", required=True)
    parser.add_argument("--output", required=True)
    parser.add_argument("--radius", type=float, required=True)
    parser.add_argument("--dimension", type=int, choices=(2, 3), default=2)
    parser.add_argument("--box", type=float, nargs=2, metavar=("LX", "LY"))
    args = parser.parse_args()

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # no particles is not worth a warning
        data = np.loadtxt(args.points, delimiter=",", skiprows=1, ndmin=2)
    if data.shape[0] == 0 or data.shape[1] < 4:
        data = np.zeros((0, 4))
    x, y, z, labels = data[:, 0], data[:, 1], data[:, 2], data[:, 3].astype(np.int64)
    particles, clusters = len(x), len(np.unique(labels))
    order = np.argsort(z, kind="stable") if args.dimension == 3 else np.arange(len(x))
    x, y, rgb = x[order], y[order], colours(labels)[order]
    if args.box:
        x, y, rgb = with_periodic_images(x, y, rgb, args.radius, args.box)

    figure, axes = plt.subplots(figsize=(8, 8))
    discs = EllipseCollection(widths=2 * args.radius, heights=2 * args.radius, angles=0, units="xy",
                              offsets=np.column_stack([x, y]), offset_transform=axes.transData,
                              facecolors=rgb, edgecolors="none")
    axes.add_collection(discs)
    if args.box:
        axes.set_xlim(0, args.box[0])
        axes.set_ylim(0, args.box[1])
        axes.add_patch(plt.Rectangle((0, 0), args.box[0], args.box[1], fill=False, linewidth=0.8))
    elif len(x):
        pad = 2 * args.radius
        axes.set_xlim(x.min() - pad, x.max() + pad)
        axes.set_ylim(y.min() - pad, y.max() + pad)
    axes.set_aspect("equal")
    view = "projected on x-y" if args.dimension == 3 else "2-D"
    axes.set_title(f"{particles} particles, {clusters} clusters ({view})")
    axes.set_xlabel("x")
    axes.set_ylabel("y")
    figure.tight_layout()
    figure.savefig(args.output, format="png", dpi=150)
    return 0


if __name__ == "__main__":
    sys.exit(main())
