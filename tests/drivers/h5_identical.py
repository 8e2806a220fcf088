#!/usr/bin/python3
"""Exit 0 if two HDF5 files hold bitwise-identical data under the given paths, 1 otherwise.

  h5_identical.py A.h5 B.h5 [PATH...]      (default PATH: /)

Every dataset and attribute below each PATH must exist in both files with the same dtype, shape
and bytes. (h5diff is not enough: it reports success for datasets of different shapes.)
"""
import sys

import h5py


def describe(f, root):
    items = {}

    def visit(name, obj):
        key = f"{root.rstrip('/')}/{name}"
        if isinstance(obj, h5py.Dataset):
            items[key] = ("dataset", obj.dtype.str, obj.shape, obj[()].tobytes() if obj.shape != () else
                          obj[()] if isinstance(obj[()], bytes) else obj[()].tobytes())
        for a, v in obj.attrs.items():
            items[f"{key}@{a}"] = ("attribute", repr(v))

    node = f[root]
    visit("", node) if isinstance(node, h5py.Dataset) else node.visititems(visit)
    for a, v in node.attrs.items():
        items[f"{root}@{a}"] = ("attribute", repr(v))
    return items


def main(argv):
    if len(argv) < 3:
        print(__doc__, file=sys.stderr)
        return 2
    paths = argv[3:] or ["/"]
    differences = 0
    with h5py.File(argv[1], "r") as a, h5py.File(argv[2], "r") as b:
        for path in paths:
            da, db = describe(a, path), describe(b, path)
            for key in sorted(set(da) | set(db)):
                if key not in da or key not in db:
                    print(f"{key}: only in {argv[1] if key in da else argv[2]}")
                    differences += 1
                elif da[key] != db[key]:
                    print(f"{key}: differs")
                    differences += 1
            print(f"{path}: {len(da)} objects compared, {differences} differences")
    return 1 if differences else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
