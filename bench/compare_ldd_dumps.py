#!/usr/bin/env python3
"""Max differences between two `bench_ldd --dump DIR` outputs (same rows in both).

    bench/compare_ldd_dumps.py BASE_DIR NEW_DIR

Per file: max |Δu|, |Δv| over the nodes, max |Δp| (pressure is relative to its mean), max
|Δ| over the 2 × 101 centre-line velocities, and whether the files are identical.
"""
import pathlib
import sys


def read(path):
    nodes, line = [], []
    for text in path.read_text().splitlines():
        kind, *values = text.split()
        (nodes if kind == "node" else line).append([float(v) for v in values])
    return nodes, line


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    base, new = pathlib.Path(sys.argv[1]), pathlib.Path(sys.argv[2])
    print("| file | max abs du, dv (nodes) | max abs dp | max abs d(centre line) | identical |")
    print("| --- | --- | --- | --- | --- |")
    for a in sorted(base.glob("*.txt")):
        b = new / a.name
        if not b.exists():
            continue
        (na, la), (nb, lb) = read(a), read(b)
        du = max(max(abs(x[0] - y[0]), abs(x[1] - y[1])) for x, y in zip(na, nb))
        dp = max(abs(x[2] - y[2]) for x, y in zip(na, nb))
        dl = max(abs(x[0] - y[0]) for x, y in zip(la, lb))
        same = a.read_bytes() == b.read_bytes()
        print(f"| {a.name} | {du:.2e} | {dp:.2e} | {dl:.2e} | {'yes' if same else 'no'} |")


if __name__ == "__main__":
    main()
