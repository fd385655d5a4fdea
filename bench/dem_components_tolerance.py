#!/usr/bin/python3
"""C/N_tot of a DEM snapshot for several contact tolerances: the components of the contact graph (centre
distance < R_i + R_j + tolerance · R_min) over the particle count, read from a binary final.vtu written by
aggkit (validation/io/particle_snapshot.hpp: positions and per-particle radii, base64 of a UInt64 byte count
and little-endian Float64 values).

  /usr/bin/python3 bench/dem_components_tolerance.py RUN/dem/final.vtu [--tolerances 0.01,0.05,0.1,0.2,0.5]

Prints one line per tolerance: tolerance, components, C/N_tot, largest component's share of the particles."""
import argparse
import base64
import struct
import xml.etree.ElementTree as ET

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.spatial import cKDTree


def float_array(piece, section, name):
    for array in piece.find(section).findall("DataArray"):
        if array.get("Name", "") == name:
            raw = base64.b64decode("".join(array.text.split()))
            (size,) = struct.unpack("<Q", raw[:8])
            if size != len(raw) - 8 or array.get("type") != "Float64":
                raise SystemExit(f"{name}: not a binary Float64 array of {size} bytes")
            return np.frombuffer(raw[8:], dtype="<f8")
    raise SystemExit(f"no DataArray {name!r} in {section}")


def main():
    p = argparse.ArgumentParser()
    p.add_argument("vtu")
    p.add_argument("--tolerances", default="0.01,0.05,0.1,0.2,0.5")
    a = p.parse_args()
    piece = ET.parse(a.vtu).getroot().find("UnstructuredGrid/Piece")
    x = float_array(piece, "Points", "").reshape(-1, 3)
    radius = float_array(piece, "PointData", "radius")
    n = len(x)
    tree = cKDTree(x)
    print("tolerance_R_min components C/N_tot largest_share")
    for tolerance in (float(t) for t in a.tolerances.split(",")):
        reach = 2 * radius.max() + tolerance * radius.min()
        pairs = np.array(sorted(tree.query_pairs(reach)), dtype=int).reshape(-1, 2)
        if len(pairs):
            d = np.linalg.norm(x[pairs[:, 0]] - x[pairs[:, 1]], axis=1)
            pairs = pairs[d < radius[pairs[:, 0]] + radius[pairs[:, 1]] + tolerance * radius.min()]
        graph = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(n, n))
        count, labels = connected_components(graph, directed=False)
        largest = np.bincount(labels).max()
        print("%g %d %.4f %.4f" % (tolerance, count, count / n, largest / n))


if __name__ == "__main__":
    main()
