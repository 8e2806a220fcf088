#!/usr/bin/python3
"""Landmarks of an orifice speed profile v_g/v_t(h) against the paper's §4.1 text (capillary-droplets,
Fig. 3(d) discussion): the first speed minimum near h/σ ≈ −0.25, the maximum (the overshoot) near
h/σ ≈ 0.3, the second local minimum near h/σ ≈ 0.5 (issue 25, item 6).

usage: profile_landmarks.py DIR [NAME...]   reads DIR/NAME.csv (the orifice driver's profile; default:
every *.csv with an h column), writes DIR/landmarks.csv (one row per profile) and prints it.

Definitions (on the sampled profile, no smoothing):
  first minimum  the smallest v_g/v_t over −1 ≤ h/σ ≤ 0.1 (contact with the wedges to the throat), and
                 the h range where v_g/v_t stays within 0.01 of it
  maximum        the largest v_g/v_t over 0 < h/σ ≤ 0.45 (after the throat, before the trailing edge),
                 if the speed falls by > 0.005 v_t after it (else none: still rising)
  second minimum the smallest v_g/v_t over h_max < h/σ ≤ 1 (the trailing edge passing the tips), if
                 the speed rises by > 0.005 v_t after it
"""
import csv
import glob
import os
import sys

PAPER = {"h_first_min": -0.25, "h_max": 0.3, "h_second_min": 0.5}


def read_profile(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    if not rows or "h" not in rows[0] or "vg_over_vt" not in rows[0]:
        return None
    return [(float(r["h"]), float(r["vg_over_vt"])) for r in rows]


def landmarks(profile):
    """(h, v) of the first minimum, the maximum and the second minimum; None where there is none: a
    maximum must be followed by a fall of > 0.005 v_t before h = 1σ (else the speed is still rising),
    a second minimum by a rise of > 0.005 v_t."""
    def pick(lo, hi, best):
        pts = [(h, v) for h, v in profile if lo < h <= hi]
        return best(pts, key=lambda p: p[1]) if pts else None
    first = pick(-1.0 - 1e-12, 0.1, min)
    peak = pick(0.0, 0.45, max)
    if peak and not any(peak[0] < h <= 1.0 and v < peak[1] - 0.005 for h, v in profile):
        peak = None
    second = pick(peak[0], 1.0, min) if peak else None
    if second and not any(second[0] < h and v > second[1] + 0.005 for h, v in profile):
        second = None
    # the extent of the first minimum: where v is within 0.01 v_t of it (the droplet nearly stops)
    plateau = [h for h, v in profile if -1.0 <= h <= 0.1 and v <= first[1] + 0.01] if first else []
    return first, peak, second, (min(plateau), max(plateau)) if plateau else None


def row_of(name, profile):
    first, peak, second, plateau = landmarks(profile)
    out = {"profile": name}
    for key, p in (("first_min", first), ("max", peak), ("second_min", second)):
        out["h_" + key] = "%.3f" % p[0] if p else ""
        out["vg_" + key] = "%.4f" % p[1] if p else ""
    out["first_min_from"] = "%.3f" % plateau[0] if plateau else ""
    out["first_min_to"] = "%.3f" % plateau[1] if plateau else ""
    return out


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    d = sys.argv[1]
    names = sys.argv[2:] or sorted(os.path.basename(p)[:-4] for p in glob.glob(os.path.join(d, "*.csv")))
    rows = []
    for name in names:
        prof = read_profile(os.path.join(d, name + ".csv"))
        if prof:
            rows.append(row_of(name, prof))
    if not rows:
        sys.exit("profile_landmarks: no orifice profiles in " + d)
    with open(os.path.join(d, "landmarks.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    print("paper (§4.1, Fig. 3d): first minimum h/σ ≈ %(h_first_min)g, maximum ≈ %(h_max)g, second minimum ≈ %(h_second_min)g"
          % PAPER)
    for r in rows:
        print("%-30s first min h = %6s (v %s; within 0.01 v_t over [%s, %s])  max h = %6s (v %s)  "
              "second min h = %6s (v %s)" %
              (r["profile"], r["h_first_min"], r["vg_first_min"], r["first_min_from"], r["first_min_to"], r["h_max"],
               r["vg_max"], r["h_second_min"], r["vg_second_min"]))


if __name__ == "__main__":
    main()
