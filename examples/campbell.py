"""Campbell diagram from the modal analysis' CSV (`cargo xtask modes`, docs/modes.md).

    python examples/campbell.py dist/modes.csv dist/campbell.png [--title TEXT]

Natural frequencies against crank speed, engine orders 1-4 drawn; the frequency
axis (--range LO:HI) reaches by default twice the 4th order at the top speed,
raised until every family's lowest mode is in view, and the legend lists only
the families in view; the discrete
bodies' artificial modes (descriptions starting with "belt pitching") and the
heavily damped modes (damping ratio above --zeta-max, default 0.1: they do not
resonate, and in running states the analysis does not converge them) are left
out and counted in a note. A mode in which a pulley's rotation carries at least a
tenth of the energy beside the part that labels it (description "... with pulley j
rotation (x %)") is drawn as that pulley's rotation. Speeds at which the drive did not settle onto a periodic
running state (CSV column `periodic` false: its steady running is not periodic,
docs/modes.md) are drawn apart, as small grey hollow markers, and named in the note.
"""

import argparse
import csv
import math
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("csv")
    ap.add_argument("png")
    ap.add_argument("--title", default="Campbell diagram")
    ap.add_argument("--range", dest="frange", default=None, metavar="LO:HI",
                    help="frequency axis [Hz], e.g. 0:400; default: from 0 to twice the 4th engine "
                         "order at the top speed, raised until every family's lowest mode is in view "
                         "(all modes stay in the CSV; the legend lists the families in view)")
    ap.add_argument("--fmax", type=float, default=None,
                    help="top of the frequency axis [Hz] (the same as --range 0:FMAX)")
    ap.add_argument("--zeta-max", type=float, default=0.1,
                    help="modes damped more than this are left out of the plot (counted)")
    a = ap.parse_args()
    rows = list(csv.DictReader(open(a.csv)))
    groups = defaultdict(lambda: ([], []))
    left_out = 0
    damped = 0
    speeds = sorted({float(r["speed_rad_s"]) for r in rows})
    # older CSVs have no such column: every speed counts as periodic there
    not_periodic = sorted({float(r["speed_rad_s"]) for r in rows
                           if r.get("periodic", "true") == "false"})
    loose = ([], [])
    for r in rows:
        d = r["description"]
        if d.startswith("belt pitching"):
            left_out += 1
            continue
        if float(r["damping_ratio"]) > a.zeta_max:
            damped += 1
            continue
        # group by kind (span k transverse, pulley j rotation, ...); a mode
        # described "span k transverse with pulley j rotation (x %)" (a
        # pulley carrying at least a tenth of its energy) joins pulley j's
        # rotation: that is the mode a drive engineer tracks against the
        # engine orders
        if " with " in d:
            d = d.split(" with ")[1].rsplit(" (", 1)[0]
        xs, ys = loose if float(r["speed_rad_s"]) in not_periodic else groups[d]
        xs.append(float(r["speed_rad_s"]) * 60 / (2 * math.pi))
        ys.append(float(r["frequency_hz"]))
    rpm_max = max(speeds) * 60 / (2 * math.pi) if speeds else 1.0
    if a.frange:
        try:
            flo, fhi = (float(x) for x in a.frange.split(":"))
        except ValueError:
            ap.error(f"--range {a.frange}: expected LO:HI in Hz")
        if not 0 <= flo < fhi:
            ap.error(f"--range {a.frange}: need 0 <= LO < HI")
    elif a.fmax:
        flo, fhi = 0.0, a.fmax
    else:
        # twice the 4th order at the top speed, raised until every family
        # (its lowest mode) is in view
        lowest = [min(ys) for _, ys in groups.values() if ys]
        flo, fhi = 0.0, max([2 * 4 * rpm_max / 60, 100.0] + [1.1 * f for f in lowest])
    # the legend lists the families with a point in view; the others are counted
    visible = {d: g for d, g in groups.items() if any(flo <= y <= fhi for y in g[1])}
    hidden = len(groups) - len(visible)
    fig, ax = plt.subplots(figsize=(9, 6))
    markers = "o^sDv<>pPX*h"
    for k, (d, (xs, ys)) in enumerate(sorted(visible.items())):
        ax.plot(xs, ys, markers[k % len(markers)], ms=5, label=d)
    if loose[0]:
        ax.plot(loose[0], loose[1], "o", ms=3, mfc="none", color="0.55",
                label="no periodic running state (not converged)")
    for order in (1, 2, 3, 4):
        ax.plot([0, rpm_max], [0, order * rpm_max / 60], "k--", lw=0.8)
        if order * rpm_max / 60 <= fhi:
            ax.annotate(f"{order}x", (rpm_max, order * rpm_max / 60), fontsize=8,
                        xytext=(3, 0), textcoords="offset points")
    ax.set_xlabel("crank speed [rpm]")
    ax.set_ylabel("natural frequency [Hz]")
    ax.set_ylim(flo, fhi)
    ax.set_xlim(-rpm_max * 0.03, rpm_max * 1.08)
    ax.set_title(a.title)
    ax.text(0.01, 0.99,
            f"{left_out} modes of the discrete bodies (belt pitching, contact, creep, "
            f"rigid rotation on the polygon) and {damped} with damping ratio > {a.zeta_max:g} left out"
            + ("" if not hidden else f"; {hidden} mode families outside {flo:g}-{fhi:g} Hz")
            + ("" if not not_periodic else
               "\nno periodic running state at " + ", ".join(f"{s * 60 / (2 * math.pi):.0f}"
                                                           for s in not_periodic)
               + " rpm: the modes there (grey) are about a trajectory near it"),
            transform=ax.transAxes, va="top", fontsize=8)
    ax.legend(fontsize=7, ncol=2, loc="upper left", bbox_to_anchor=(0.0, 0.95))
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(a.png, dpi=110)
    print(f"wrote {a.png} ({left_out} artificial and {damped} heavily damped modes left out)")


if __name__ == "__main__":
    main()
