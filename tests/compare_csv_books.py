#!/usr/bin/env python3
"""compare_csv_books.py ONE SPLIT REL COLUMN [COLUMN ...]

Compares a driver's CSV from one process (ONE) with the same run split over MPI ranks (SPLIT):
the same header and rows, every field byte for byte the same, except in the named COLUMNs (energy
books that a split sums in another order), where |one - split| <= REL x the column's largest
magnitude in ONE. Exits 1 naming the first difference, 0 when the files agree so."""
import csv
import sys


def main(argv):
    if len(argv) < 5:
        print(__doc__)
        return 2
    one_path, split_path, rel, columns = argv[1], argv[2], float(argv[3]), set(argv[4:])
    with open(one_path, newline="") as f:
        one = list(csv.reader(f))
    with open(split_path, newline="") as f:
        split = list(csv.reader(f))
    if not one or one[0] != split[0]:
        print(f"headers differ: {one[0] if one else None} against {split[0] if split else None}")
        return 1
    header = one[0]
    missing = columns - set(header)
    if missing:
        print(f"no column {sorted(missing)} in {one_path}")
        return 1
    if len(one) != len(split):
        print(f"{len(one) - 1} rows in one process's file, {len(split) - 1} in the split's")
        return 1
    scale = {c: max(abs(float(row[header.index(c)])) for row in one[1:]) for c in columns}
    worst = {c: 0.0 for c in columns}
    for n, (a, b) in enumerate(zip(one[1:], split[1:]), start=2):
        for c, x, y in zip(header, a, b):
            if c in columns:
                d = abs(float(x) - float(y))
                worst[c] = max(worst[c], d)
                if d > rel * scale[c]:
                    print(f"line {n}, {c}: {x} against {y} (more than {rel} x {scale[c]})")
                    return 1
            elif x != y:
                print(f"line {n}, {c}: {x} against {y} (must be the same bits)")
                return 1
    print("same bits but the books; largest book differences: " +
          ", ".join(f"{c} {worst[c]:.3g} (scale {scale[c]:.3g})" for c in sorted(columns)))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
