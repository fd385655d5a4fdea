"""Analysing a configuration produced outside aggkit: a diffusion-limited-like random walk aggregate built
here with numpy stands in for another code's output (positions of equal discs of radius R).

    PYTHONPATH=build/python /usr/bin/python3 examples/python/analyse_configuration.py
"""
import numpy as np

from aggkit import analysis

rng = np.random.default_rng(1)
R = 0.5
positions = [np.zeros(2)]
while len(positions) < 400:  # each new disc sticks, touching, to a random disc of the aggregate
    anchor = positions[rng.integers(len(positions))]
    angle = rng.uniform(0, 2 * np.pi)
    candidate = anchor + 2 * R * np.array([np.cos(angle), np.sin(angle)])
    if min(np.linalg.norm(candidate - p) for p in positions) >= 2 * R * (1 - 1e-9):
        positions.append(candidate)
x = np.array(positions)

labels = analysis.contact_clusters(x, R)
sizes, counts = analysis.size_distribution(labels)
print("clusters:", dict(zip(sizes.tolist(), counts.tolist())))
print("relative contacts N_c:", round(analysis.relative_contacts(x, R), 4))
g = analysis.gyration(x)
print("radius of gyration:", round(g["radius_of_gyration"], 3), " aspect ratio:", round(g["aspect_ratio"], 3))
fit = analysis.mass_radius_dimension(x, R)
print(f"mass-radius dimension: {fit['dimension']:.3f} ± {fit['standard_error']:.3f} on [{fit['fit_min']:.2f}, {fit['fit_max']:.2f}]")
