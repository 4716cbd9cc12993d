"""A drawing of any drive: `python -m beltdrive.layout FILE.ssv [--set N=V ...]`.

The drawing is the physics core's own mounted layout, drawn by
`cargo xtask layout` (docs/layout.md): an SVG and a PNG with the pulleys
(names, radii, wrap angles), the belt path, its running direction, the span
numbers with their free lengths and their tensions at the loads given (tight
and slack side), and the tensioner arms. This module runs that command from
the repository the package sits in, so a study can draw the drive of any
parameter set beside its results.
"""
import argparse
import pathlib
import subprocess
import sys

REPO = pathlib.Path(__file__).resolve().parents[2]


def draw(ssv=None, out=None, sets=(), names=(), title=None) -> pathlib.Path:
    """Draws the drive of `ssv` (None: the FMU's default drive) with the
    `NAME=VALUE` overrides `sets`; `names` names the pulleys in order.
    Writes `out` (an .svg path, default dist/layout.svg) and the PNG beside
    it; returns the PNG's path."""
    cmd = ["cargo", "xtask", "layout", "--"]
    if ssv is not None:
        cmd += ["--ssv", str(pathlib.Path(ssv).resolve())]
    for s in sets:
        cmd += ["--set", s]
    if names:
        cmd += ["--names", ",".join(names)]
    if title:
        cmd += ["--title", title]
    svg = pathlib.Path(out).resolve() if out else REPO / "dist" / "layout.svg"
    cmd += ["--out", str(svg)]
    subprocess.run(cmd, cwd=REPO, check=True)
    return svg.with_suffix(".png")


def main(argv=None):
    ap = argparse.ArgumentParser(prog="python -m beltdrive.layout", description=__doc__.splitlines()[0])
    ap.add_argument("ssv", nargs="?", help="parameter set (.ssv); default: the FMU's default drive")
    ap.add_argument("--set", action="append", default=[], metavar="NAME=VALUE")
    ap.add_argument("--names", default="", help="pulley names in order, comma-separated")
    ap.add_argument("--title")
    ap.add_argument("--out", help="SVG path (the PNG goes beside it); default dist/layout.svg")
    a = ap.parse_args(argv)
    names = [n for n in a.names.split(",")] if a.names else []
    print(draw(a.ssv, a.out, a.set, names, a.title))
    return 0


if __name__ == "__main__":
    sys.exit(main())
