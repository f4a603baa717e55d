#!/usr/bin/env python3
"""Writes the node set of the Peridigm fragmenting-cylinder example (a tube of height 100 mm,
radii 20 and 25 mm): one node at the centroid of each ring-sector cell, `cells` cells through
the wall (Peridigm's example: 5), as many around the mean circumference and along the height
as make the cells about square, each node moved by a uniform random amount of at most 0.001
of the cell size in each direction (Python's random, seed 42, as the example does) to break
the symmetry. Format: x y z block volume (a peri node_file, bench/peers/README.md).

  cylinder_nodes.py CELLS OUT
"""
import math
import random
import sys


def main():
    cells, out = int(sys.argv[1]), sys.argv[2]
    height, r_out, r_in = 0.100, 0.025, 0.020
    size = (r_out - r_in) / cells
    around = int(2.0 * math.pi * 0.5 * (r_out + r_in) / size + 0.5)
    along = int(height / size + 0.5)
    half = math.pi / around  # half the angle of a sector
    rows = []
    for k in range(along):
        for j in range(around):
            for i in range(cells):
                a, b = r_in + i * size, r_in + (i + 1) * size
                # centroid of the ring sector: the two circular sectors' centroids 2 r sin(h)/(3 h)
                area_b, area_a = half * b * b, half * a * a
                centroid = (2 * b * math.sin(half) / (3 * half) * area_b - 2 * a * math.sin(half) / (3 * half) * area_a) / (area_b - area_a)
                angle = (2 * j + 1) * half
                rows.append([centroid * math.cos(angle), centroid * math.sin(angle), (k + 0.5) * height / along,
                             (area_b - area_a) * height / along])
    rng = random.Random(42)
    for r in rows:
        for c in range(3):
            r[c] += (2.0 * rng.random() - 1.0) * 0.001 * size
    with open(out, "w") as f:
        for r in rows:
            f.write("%r %r %r 1 %r\n" % (r[0], r[1], r[2], r[3]))
    print("%d nodes, cell %g m" % (len(rows), size))


if __name__ == "__main__":
    main()
