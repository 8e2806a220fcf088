#!/usr/bin/python3
"""Plot a driver's observables CSV (step,time,<observable>...) as one panel per observable.

  scripts/plot_observables.py RUN.csv [OUT.png]      (default OUT: RUN.png)

Uses Debian's python3-matplotlib (installed by scripts/bootstrap).
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(argv):
    if len(argv) not in (2, 3):
        print(__doc__, file=sys.stderr)
        return 2
    source = argv[1]
    target = argv[2] if len(argv) == 3 else source.rsplit(".", 1)[0] + ".png"
    with open(source, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        print(f"{source}: no rows", file=sys.stderr)
        return 1
    names = [k for k in rows[0] if k not in ("step", "time")]
    time = [float(r["time"]) for r in rows]
    fig, axes = plt.subplots(len(names), 1, sharex=True, figsize=(7, 1.8 * len(names) + 0.6))
    axes = axes if len(names) > 1 else [axes]
    for ax, name in zip(axes, names):
        ax.plot(time, [float(r[name]) for r in rows], lw=1.2)
        ax.set_ylabel(name.replace("_", " "), fontsize=9)
        ax.grid(alpha=0.3)
    axes[-1].set_xlabel("time")
    fig.suptitle(source, fontsize=9)
    fig.tight_layout()
    fig.savefig(target, dpi=120)
    print(f"wrote {target}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
