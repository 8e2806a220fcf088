#!/usr/bin/env python3
"""Runs the code cells of a Jupyter notebook in order, in one namespace, with matplotlib's Agg backend
(no Jupyter needed): the notebook test of examples/orifice.ipynb (docs/python.md).

    run_notebook.py NOTEBOOK.ipynb
"""
import json
import sys

import matplotlib

matplotlib.use("Agg")

nb = json.load(open(sys.argv[1]))
namespace = {"__name__": "__main__"}
cells = [c for c in nb["cells"] if c["cell_type"] == "code"]
for k, cell in enumerate(cells, 1):
    source = "".join(cell["source"])
    exec(compile(source, "%s[cell %d]" % (sys.argv[1], k), "exec"), namespace)
print("ran %d code cells of %s" % (len(cells), sys.argv[1]))
