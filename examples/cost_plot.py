"""Cost against belt speed from the speed benchmark's table (docs/benchmarks.md).

    python examples/cost_plot.py docs/benchmarks.md docs/benchmarks/cost-vs-belt-speed.svg

`cargo xtask bench` runs it after it has regenerated the page. It reads the table of the generated section
whose header starts "| drive | crank speed [rpm] | belt speed [m/s] |" (`cargo bench --bench belt -- speeds`)
and draws the CPU time per simulated second (1 / real-time factor) against the belt speed, one line per
drive and method, on a logarithmic axis with real time marked: below the line a drive runs faster than
real time.
"""

import argparse
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

HEADER = "| drive | crank speed [rpm] | belt speed [m/s] |"


def rows(text):
    """(drive, belt speed, method, real-time factor) of every row of the table."""
    lines = text.splitlines()
    start = next((i for i, line in enumerate(lines) if line.startswith(HEADER)), None)
    if start is None:
        raise SystemExit(f"no table starting {HEADER!r}: run `cargo xtask bench` first")
    out = []
    for line in lines[start + 2:]:
        if not line.startswith("|"):
            break
        cells = [c.strip() for c in line.strip("|").split("|")]
        out.append((cells[0], float(cells[2]), cells[3], float(cells[4])))
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("page", help="docs/benchmarks.md")
    ap.add_argument("out", help="the picture (.svg or .png)")
    a = ap.parse_args()
    with open(a.page, encoding="utf-8") as f:
        table = rows(f.read())
    series = defaultdict(list)
    for drive, v, method, rtf in table:
        series[(drive, method)].append((v, 1.0 / rtf))
    plt.rcParams["svg.hashsalt"] = "beltdrive"
    fig, ax = plt.subplots(figsize=(7.5, 4.8))
    colours = {"stiff": "tab:blue", "RKF45": "tab:orange"}
    markers = {"accessory-drive-4": "o", "accessory-drive-tensioner": "s", "5PK (FMU default)": "D"}
    for (drive, method), pts in sorted(series.items()):
        pts.sort()
        ax.plot(
            [p[0] for p in pts],
            [p[1] for p in pts],
            marker=markers.get(drive, "^"),
            color=colours.get(method, "grey"),
            linestyle="-" if drive != "accessory-drive-tensioner" else "--",
            label=f"{drive}, {method}",
        )
    ax.axhline(1.0, color="black", linewidth=0.8)
    ax.text(0.5, 1.05, "real time", fontsize=8, va="bottom")
    ax.set_yscale("log")
    ax.set_xlabel("belt speed [m/s]")
    ax.set_ylabel("CPU seconds per simulated second")
    ax.set_title("Cost against belt speed (relTol 1e-4, 1 ms communication steps, one core)", fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(a.out, metadata={"Date": None} if a.out.endswith(".svg") else None)
    print(a.out)


if __name__ == "__main__":
    main()
