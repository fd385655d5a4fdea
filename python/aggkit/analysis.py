"""Analysis of particle configurations from any code: numpy arrays of positions (N×2 or N×3) of spheres of
radius R (a number) or of their own radii (an array, one per particle: contact ranges are then those of each
pair, R_i + R_j, with their mean as the reference radius), with an optional box (its sides) that may be
periodic. The same functions the particle engines' observables use."""
from ._aggkit import (box_counting_dimension, contact_clusters, gyration, mass_radius_dimension, pair_distribution,
                      relative_contacts)

__all__ = ["contact_clusters", "size_distribution", "relative_contacts", "pair_distribution", "gyration",
           "box_counting_dimension", "mass_radius_dimension"]


def size_distribution(labels):
    """(sizes, counts): the cluster sizes present and how many clusters have each, from cluster labels."""
    import numpy as np
    sizes = np.bincount(np.asarray(labels, dtype=np.int64))
    present, counts = np.unique(sizes[sizes > 0], return_counts=True)
    return present, counts
