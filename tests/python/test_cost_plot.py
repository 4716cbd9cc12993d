"""examples/cost_plot.py, the picture of docs/benchmarks.md's speeds table that `cargo xtask bench`
draws (no FMU needed): it reads the table the page carries and draws every drive and method of it."""

import importlib.util
import pathlib
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parents[2]


def load():
    spec = importlib.util.spec_from_file_location("cost_plot", ROOT / "examples/cost_plot.py")
    m = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(m)
    return m


def test_reads_every_row_of_the_pages_speeds_table():
    """The page's table: two accessory sets at four crank speeds and the 5PK drive, each with both
    methods (18 rows); belt speeds rise with the crank speed, the real-time factors are positive."""
    rows = load().rows((ROOT / "docs/benchmarks.md").read_text(encoding="utf-8"))
    assert len(rows) == 18, rows
    assert {r[2] for r in rows} == {"stiff", "RKF45"}
    for drive in ("accessory-drive-4", "accessory-drive-tensioner"):
        for method in ("stiff", "RKF45"):
            v = [r[1] for r in rows if r[0] == drive and r[2] == method]
            assert len(v) == 4 and v == sorted(v) and v[0] > 0, (drive, method, v)
    assert all(r[3] > 0 for r in rows)


def test_draws_the_svg_without_a_date(tmp_path):
    """The command the page gives writes an SVG with one line per drive and method and no date in its
    metadata (docs carry none)."""
    out = tmp_path / "cost.svg"
    subprocess.run(
        [sys.executable, str(ROOT / "examples/cost_plot.py"), str(ROOT / "docs/benchmarks.md"), str(out)],
        check=True,
        cwd=ROOT,
    )
    text = out.read_text(encoding="utf-8")
    assert text.count("accessory-drive-tensioner, stiff") == 1, "legend entry"
    assert "<dc:date>" not in text


def test_refuses_a_page_without_the_table(tmp_path):
    page = tmp_path / "page.md"
    page.write_text("# no table here\n", encoding="utf-8")
    r = subprocess.run(
        [sys.executable, str(ROOT / "examples/cost_plot.py"), str(page), str(tmp_path / "x.svg")],
        capture_output=True,
        text=True,
        cwd=ROOT,
    )
    assert r.returncode != 0 and "cargo xtask bench" in r.stderr
