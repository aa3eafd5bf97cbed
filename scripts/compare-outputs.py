#!/usr/bin/env python3
"""Compares two sweep outputs, both ways: the replica files (every dataset byte for byte, every
attribute, the same objects on both sides), the index (sweep.h5 likewise, its external links by
target), summary.csv, summary.json, phase.json and spec.json. What describes the run rather than its
result is left out: wall_s (the replica's wall-clock time, an attribute and an index column),
resumes (how often it went on from a checkpoint or an extension, likewise) and git_commit (the
commit the binary was built from). Exits 1 at the first difference, naming it.
`--ignore-attr NAME` (repeatable) skips further attributes and columns, e.g. `spec` and `spec_hash`
when the canonical spec gained fields with defaults between the two builds.

    .venv/bin/python scripts/compare-outputs.py OUT_A OUT_B
"""

import argparse
import csv
import glob
import json
import os
import sys

import h5py
import numpy as np

RUN_ATTRIBUTES = {"wall_s", "git_commit", "resumes"}


class Differ(Exception):
    """The first difference found, as a message."""


def _same_value(v, w) -> bool:
    v, w = np.asarray(v), np.asarray(w)
    if v.shape != w.shape or v.dtype.kind != w.dtype.kind:
        return False
    return bool(np.array_equal(v, w) or (v.dtype.kind == "f" and np.array_equal(v, w, equal_nan=True)))


def _objects(f: h5py.File):
    """Every object of `f` by path (the root as "/"), and every soft or external link by target."""
    objects, links = {"/": f}, {}

    def walk(group, prefix):
        for key in group:
            path = f"{prefix}/{key}"
            link = group.get(key, getlink=True)
            if isinstance(link, h5py.ExternalLink):
                links[path] = (link.filename, link.path)
            elif isinstance(link, h5py.SoftLink):
                links[path] = link.path
            else:
                obj = group[key]
                objects[path] = obj
                if isinstance(obj, h5py.Group):
                    walk(obj, path)

    walk(f, "")
    return objects, links


def compare_h5(pa: str, pb: str, ignored, counts) -> None:
    with h5py.File(pa, "r") as x, h5py.File(pb, "r") as y:
        ox, lx = _objects(x)
        oy, ly = _objects(y)
        # An ignored column of the index is a dataset of that name: skipped on both sides.
        ox = {k: v for k, v in ox.items() if os.path.basename(k) not in ignored}
        oy = {k: v for k, v in oy.items() if os.path.basename(k) not in ignored}
        name = os.path.basename(pa)
        for only, side in ((set(ox) - set(oy), "A"), (set(oy) - set(ox), "B")):
            if only:
                raise Differ(f"{name}: {sorted(only)[0]} only in {side}")
        if lx != ly:
            raise Differ(f"{name}: links differ")
        for path in sorted(ox):
            a, b = ox[path], oy[path]
            if isinstance(a, h5py.Dataset) != isinstance(b, h5py.Dataset):
                raise Differ(f"{name}:{path} is a dataset on one side only")
            ka = set(a.attrs) - ignored
            kb = set(b.attrs) - ignored
            if ka != kb:
                raise Differ(f"{name}:{path}@{sorted(ka ^ kb)[0]} on one side only")
            for key in sorted(ka):
                if not _same_value(a.attrs[key], b.attrs[key]):
                    raise Differ(f"{name}:{path}@{key} differs")
                counts["attributes"] += 1
            if isinstance(a, h5py.Dataset):
                if os.path.basename(path) in ignored:
                    continue
                va, vb = a[()], b[()]
                if a.dtype.kind == "O":
                    # Variable-length strings: the values, not the pointers that hold them.
                    same = np.asarray(va).tolist() == np.asarray(vb).tolist()
                else:
                    same = va.tobytes() == vb.tobytes()
                if a.dtype != b.dtype or a.shape != b.shape or not same:
                    raise Differ(f"{name}:{path} differs")
                counts["datasets"] += 1


def _rows_csv(path, ignored):
    with open(path, newline="") as f:
        return [{k: v for k, v in row.items() if k not in ignored} for row in csv.DictReader(f)]


def _rows_json(path, ignored):
    with open(path) as f:
        rows = json.load(f)
    if isinstance(rows, list):
        return [{k: v for k, v in r.items() if k not in ignored} if isinstance(r, dict) else r for r in rows]
    return rows


def compare(a: str, b: str, ignored=RUN_ATTRIBUTES) -> str:
    """The summary line of two equal outputs; raises Differ at the first difference."""
    names_a = sorted(os.path.basename(p) for p in glob.glob(f"{a}/replicas/*.h5"))
    names_b = sorted(os.path.basename(p) for p in glob.glob(f"{b}/replicas/*.h5"))
    if names_a != names_b:
        only = sorted(set(names_a) ^ set(names_b))
        raise Differ(f"the replica file sets differ ({only[0]} on one side only)")
    counts = {"datasets": 0, "attributes": 0}
    for name in names_a:
        compare_h5(f"{a}/replicas/{name}", f"{b}/replicas/{name}", ignored, counts)
    index = []
    for name, read in (("sweep.h5", None), ("summary.csv", _rows_csv), ("summary.json", _rows_json),
                       ("phase.json", _rows_json), ("spec.json", _rows_json)):
        pa, pb = os.path.join(a, name), os.path.join(b, name)
        if os.path.exists(pa) != os.path.exists(pb):
            raise Differ(f"{name} on one side only")
        if not os.path.exists(pa):
            continue
        if read is None:
            compare_h5(pa, pb, ignored, counts)
        elif read(pa, ignored) != read(pb, ignored):
            raise Differ(f"{name} differs")
        index.append(name)
    return (f"{len(names_a)} replica files: {counts['datasets']} datasets bit-identical, "
            f"{counts['attributes']} attributes equal ({', '.join(sorted(ignored))} excluded); "
            f"index equal: {', '.join(index) or 'none'}")


def main(a: str, b: str, ignored=RUN_ATTRIBUTES) -> int:
    for d in (a, b):
        if not os.path.isdir(d):
            print(f"error: {d} is not a sweep output directory", file=sys.stderr)
            return 2
    try:
        print(compare(a, b, ignored))
    except Differ as e:
        print(f"differ: {e}")
        return 1
    return 0


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("out_a")
    parser.add_argument("out_b")
    parser.add_argument("--ignore-attr", action="append", default=[], metavar="NAME",
                        help="also skip this attribute or index column (repeatable)")
    args = parser.parse_args()
    sys.exit(main(args.out_a, args.out_b, RUN_ATTRIBUTES | set(args.ignore_attr)))
