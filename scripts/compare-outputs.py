#!/usr/bin/env python3
"""Compares the replica files of two sweep outputs: every dataset byte for byte and every attribute
but the two that describe the run rather than its result: wall_s (the replica's wall-clock time) and
git_commit (the commit the binary was built from, which differs whenever two builds are compared).
Exits 1 at the first difference. `--ignore-attr NAME` (repeatable) skips further attributes, e.g.
`spec` and `spec_hash` when the canonical spec gained fields with defaults between the two builds.

    .venv/bin/python scripts/compare-outputs.py OUT_A OUT_B
"""

import argparse
import glob
import os
import sys

import h5py
import numpy as np

RUN_ATTRIBUTES = {"wall_s", "git_commit"}


def main(a: str, b: str, ignored=RUN_ATTRIBUTES) -> int:
    names_a = sorted(os.path.basename(p) for p in glob.glob(f"{a}/replicas/*.h5"))
    names_b = sorted(os.path.basename(p) for p in glob.glob(f"{b}/replicas/*.h5"))
    if names_a != names_b:
        print("the replica file sets differ")
        return 1
    counts = {"datasets": 0, "attributes": 0}
    for name in names_a:
        with h5py.File(f"{a}/replicas/{name}", "r") as x, h5py.File(f"{b}/replicas/{name}", "r") as y:
            def visit(path, obj, y=y, name=name):
                other = y[path]
                for key, value in obj.attrs.items():
                    if key in ignored:
                        continue
                    v, w = np.asarray(value), np.asarray(other.attrs[key])
                    same = v.shape == w.shape and (
                        np.array_equal(v, w) or (v.dtype.kind == "f" and np.array_equal(v, w, equal_nan=True))
                    )
                    if not same:
                        raise SystemExit(f"{name}:{path}@{key} differs")
                    counts["attributes"] += 1
                if isinstance(obj, h5py.Dataset):
                    if obj[()].tobytes() != other[()].tobytes() or obj.dtype != other.dtype:
                        raise SystemExit(f"{name}:{path} differs")
                    counts["datasets"] += 1

            x.visititems(visit)
    print(f"{len(names_a)} replica files: {counts['datasets']} datasets bit-identical, "
          f"{counts['attributes']} attributes equal ({', '.join(sorted(ignored))} excluded)")
    return 0


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("out_a")
    parser.add_argument("out_b")
    parser.add_argument("--ignore-attr", action="append", default=[], metavar="NAME",
                        help="also skip this attribute (repeatable)")
    args = parser.parse_args()
    sys.exit(main(args.out_a, args.out_b, RUN_ATTRIBUTES | set(args.ignore_attr)))
