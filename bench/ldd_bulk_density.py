#!/usr/bin/env python3
"""The compression of an LDD free-surface run's bulk, from its node frames (docs/ldd.md, "Water column").

    bench/ldd_bulk_density.py RUN_DIR [--smoothing-ratio R] [--disk-radius N]

RUN_DIR is a finished `rheosim run` (or bench_ldd run) folder of a 2D free-surface case: its
case.yaml (resolution.spacing) and frames/nodes_*.vtk (legacy binary VTK: positions, kind). For
every frame it takes the fluid nodes whose kernel support (h = R Δ, R = 1.6 as the solver's
default) holds no free-surface or splash node — the nodes whose kernel sum Σ W(r, h) the void does
not truncate — and prints their mean kernel sum against the rest value ρ₀ (the median over the
first frame's fluid nodes, as the solver takes it; summary.json's `bulk_compression` is the
largest departure of the same mean). With h = 1.6 Δ the node's own W(0) dominates the sum, so
it is not proportional to the number density (a lattice squeezed 5 % reads +2.6 %): it says
whether and where the bulk is compressed. How much, it prints the area under the
free surface (in each Δ-wide column, the top fluid node plus Δ/2 above the lowest fluid node less
Δ/2), which is the fluid's area while the surface is single-valued (no overturning jet, no splash
above a void). The run's own `volume_drift` counts every node near the surface too, where the
truncated sums read as expansion. Last, the bulk's nodes per Δ², counted in disks of
--disk-radius spacings (default 4) that hold no free-surface, splash or wall node: a count that,
unlike the kernel sum, does not depend on the nodes' arrangement (the first frame's lattice reads
1.000).
"""
import argparse
import glob
import math
import os
import re
import struct
import sys

KINDS = {"interior": 0, "surface": 1, "splash": 2, "wall": 3, "corner": 4, "idle_wall": 5}
FORMATS = {"float": ("f", 4), "double": ("d", 8), "int": ("i", 4), "unsigned_char": ("B", 1), "char": ("b", 1)}


def read_vtk_fields(path):
    """Every array of a legacy binary POLYDATA file as rheosim writes it, by name ("points": x, y, z
    per node; "velocity": three components per node; "kind", "pressure", ...: one per node), and
    the node count."""
    data = open(path, "rb").read()
    pos = 0
    fields = {}

    def line():
        nonlocal pos
        end = data.index(b"\n", pos)
        text = data[pos:end].decode("latin1")
        pos = end + 1
        return text

    def values(count, type_name):
        nonlocal pos
        code, size = FORMATS[type_name]
        out = struct.unpack(">%d%s" % (count, code), data[pos : pos + count * size])
        pos += count * size
        return out

    for _ in range(4):
        line()
    n = 0
    while pos < len(data):
        words = line().split()
        if not words:
            continue
        if words[0] == "POINTS":
            n = int(words[1])
            fields["points"] = values(3 * n, words[2])
        elif words[0] in ("VERTICES", "LINES", "POLYGONS"):
            pos += int(words[2]) * 4
        elif words[0] == "POINT_DATA":
            continue
        elif words[0] == "SCALARS":
            components = int(words[3]) if len(words) > 3 else 1
            line()  # LOOKUP_TABLE
            fields[words[1]] = values(n * components, words[2])
        elif words[0] == "VECTORS":
            fields[words[1]] = values(3 * n, words[2])
        elif words[0] == "FIELD":
            for _ in range(int(words[2])):
                name, components, count, type_name = line().split()
                fields[name] = values(int(components) * int(count), type_name)
        else:
            sys.exit(f"{path}: unexpected VTK section {words[0]}")
    return fields, n


def read_vtk(path):
    """Positions (x, y) and kinds of a legacy binary POLYDATA file as rheosim writes it."""
    fields, n = read_vtk_fields(path)
    points = fields["points"]
    return [(points[3 * i], points[3 * i + 1]) for i in range(n)], [int(k) for k in fields["kind"]]


def kernel_sums(points, h):
    """Σ_j W(|x_i − x_j|, h) over all nodes, W = (1 − r/h)³ (the solver's kernel), and the
    neighbour lists within h."""
    grid = {}
    for i, (x, y) in enumerate(points):
        grid.setdefault((math.floor(x / h), math.floor(y / h)), []).append(i)
    sums, neighbours = [0.0] * len(points), [[] for _ in points]
    for i, (x, y) in enumerate(points):
        cx, cy = math.floor(x / h), math.floor(y / h)
        total = 0.0
        for gx in (cx - 1, cx, cx + 1):
            for gy in (cy - 1, cy, cy + 1):
                for j in grid.get((gx, gy), ()):
                    r = math.hypot(points[j][0] - x, points[j][1] - y)
                    if r < h:
                        s = 1.0 - r / h
                        total += s * s * s
                        if j != i:
                            neighbours[i].append(j)
        sums[i] = total
    return sums, neighbours


def bulk_number_density(points, kinds, spacing, radius):
    """Nodes per Δ² in disks of the bulk: disks of `radius` centred on a grid of step 1.37 Δ (not
    commensurate with the initial lattice, so the centres sample every offset within a cell and a
    lattice reads 1), those that hold no free-surface, splash or wall node and at least one
    interior node. Unlike a kernel sum, a count over a disk does not depend on how the nodes are
    arranged, only on how many there are. Returns (density, disks)."""
    grid = {}
    for i, (x, y) in enumerate(points):
        grid.setdefault((math.floor(x / radius), math.floor(y / radius)), []).append(i)
    xs = [x for x, _ in points]
    ys = [y for _, y in points]
    step = 1.37 * spacing
    total, disks = 0, 0
    y = min(ys)
    while y < max(ys):
        x = min(xs)
        while x < max(xs):
            cx, cy = math.floor(x / radius), math.floor(y / radius)
            count, open_disk = 0, False
            for gx in (cx - 1, cx, cx + 1):
                for gy in (cy - 1, cy, cy + 1):
                    for j in grid.get((gx, gy), ()):
                        if math.hypot(points[j][0] - x, points[j][1] - y) < radius:
                            if kinds[j] != KINDS["interior"]:
                                open_disk = True
                            count += 1
            if count > 0 and not open_disk:
                total += count
                disks += 1
            x += step
        y += step
    if disks == 0:
        return None, 0
    return total / disks * spacing * spacing / (math.pi * radius * radius), disks


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("run_dir")
    parser.add_argument("--smoothing-ratio", type=float, default=1.6)
    parser.add_argument("--disk-radius", type=float, default=4.0, help="in spacings (the disk count's radius)")
    args = parser.parse_args()
    case = open(os.path.join(args.run_dir, "case.yaml")).read()
    match = re.search(r"spacing:\s*([0-9.eE+-]+)", case)
    if not match:
        sys.exit(f"{args.run_dir}/case.yaml: no resolution.spacing")
    spacing = float(match.group(1))
    h = args.smoothing_ratio * spacing
    frames = sorted(glob.glob(os.path.join(args.run_dir, "frames", "nodes_*.vtk")))
    if not frames:
        sys.exit(f"{args.run_dir}/frames: no nodes_*.vtk")
    fluid_kinds = (KINDS["interior"], KINDS["surface"], KINDS["splash"])
    open_kinds = (KINDS["surface"], KINDS["splash"])
    rest = None
    radius = args.disk_radius * spacing
    print(f"{args.run_dir}: bulk kernel density, Δ = {spacing} m, h = {h:.4g} m")
    print(
        "| frame | fluid nodes | bulk nodes | bulk ρ̄/ρ₀ − 1 | largest |ρ/ρ₀ − 1| | area under the surface, vs first frame "
        "| bulk nodes per Δ² (disks) |"
    )
    print("| --- | --- | --- | --- | --- | --- | --- |")
    area0 = None
    worst = 0.0
    for path in frames:
        points, kinds = read_vtk(path)
        sums, neighbours = kernel_sums(points, h)
        fluid = [i for i, k in enumerate(kinds) if k in fluid_kinds]
        if rest is None:
            values = sorted(sums[i] for i in fluid)
            rest = values[len(values) // 2]
        bulk = [
            i for i in fluid if kinds[i] == KINDS["interior"] and not any(kinds[j] in open_kinds for j in neighbours[i])
        ]
        continuum = [i for i in fluid if kinds[i] != KINDS["splash"]]
        tops = {}
        for i in continuum:
            column = math.floor(points[i][0] / spacing)
            tops[column] = max(tops.get(column, -math.inf), points[i][1])
        floor = min(points[i][1] for i in continuum) - spacing / 2
        area = sum((top + spacing / 2 - floor) * spacing for top in tops.values())
        if area0 is None:
            area0 = area
        area_change = f"{100 * (area / area0 - 1):+.2f} %"
        density, disks = bulk_number_density(points, kinds, spacing, radius)
        disk_change = "" if density is None else f"{density:.3f} ({disks} disks)"
        if not bulk:
            print(f"| {os.path.basename(path)} | {len(fluid)} | 0 | | | {area_change} | {disk_change} |")
            continue
        mean = sum(sums[i] for i in bulk) / len(bulk)
        largest = max(abs(sums[i] / rest - 1) for i in bulk)
        worst = max(worst, abs(mean / rest - 1))
        print(
            f"| {os.path.basename(path)} | {len(fluid)} | {len(bulk)} | {100 * (mean / rest - 1):+.2f} % | "
            f"{100 * largest:.1f} % | {area_change} | {disk_change} |"
        )
    print(f"largest departure of the bulk's mean kernel sum from ρ₀: {100 * worst:.2f} %")


if __name__ == "__main__":
    main()
