"""Plots of a study's results table: every result against each varied
parameter, and a 2-D map of every result when two parameters are varied.
Failed runs are marked with a red cross."""
from __future__ import annotations

import pathlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def _label(study, name):
    p = next((p for p in study.parameters if p.name == name), None)
    return f"{name} [{p.unit}]" if p is not None and p.unit not in (None, "", "1") else name


def _safe(name):
    return "".join(c if c.isalnum() or c in "._-" else "_" for c in name)


def _vs_parameter(ax, study, table, col, pname):
    ok = table["status"] == "ok"
    others = [p.name for p in study.parameters if p.name != pname]
    if study.design == "grid" and len(others) == 1:
        other = others[0]
        for v, g in table[ok].groupby(other):
            g = g.sort_values(pname)
            ax.plot(g[pname], g[col], "o-", ms=3, label=f"{other} = {v:g}")
        ax.legend(fontsize=7)
    else:
        ax.plot(table.loc[ok, pname], table.loc[ok, col], "o", ms=3)
    bad = table[~ok]
    if len(bad):
        y0 = np.nanmin(table.loc[ok, col]) if ok.any() else 0.0
        ax.plot(bad[pname], np.full(len(bad), y0), "rx", label="failed")
    ax.set_xlabel(_label(study, pname))
    ax.set_ylabel(col)
    ax.grid(alpha=0.3)


def _map(ax, fig, study, table, col):
    px, py = study.parameters[0].name, study.parameters[1].name
    ok = table["status"] == "ok"
    if study.design == "grid":
        xs, ys = study.parameters[0].values, study.parameters[1].values
        z = np.full((len(ys), len(xs)), np.nan)
        for _, r in table[ok].iterrows():
            z[ys.index(r[py]), xs.index(r[px])] = r[col]
        m = ax.pcolormesh(xs, ys, z, shading="nearest", cmap="viridis")
        for j, y in enumerate(ys):
            for i, x in enumerate(xs):
                if np.isfinite(z[j, i]):
                    ax.text(x, y, f"{z[j, i]:.3g}", ha="center", va="center", fontsize=6,
                            color="w")
    else:
        m = ax.scatter(table.loc[ok, px], table.loc[ok, py], c=table.loc[ok, col], cmap="viridis")
    bad = table[~ok]
    if len(bad):
        ax.plot(bad[px], bad[py], "rx", ms=8)
    fig.colorbar(m, ax=ax, label=col)
    ax.set_xlabel(_label(study, px))
    ax.set_ylabel(_label(study, py))


def plot_study(study, table, out_dir) -> list[pathlib.Path]:
    out_dir = pathlib.Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    cols = [c for r in study.results for c in r.columns()]
    names = [p.name for p in study.parameters]
    paths = []
    for col in cols:
        n = len(names) + (1 if len(names) == 2 else 0)
        fig, axes = plt.subplots(1, n, figsize=(4.2 * n, 3.4), squeeze=False)
        for ax, pname in zip(axes[0], names):
            _vs_parameter(ax, study, table, col, pname)
        if len(names) == 2:
            _map(axes[0][-1], fig, study, table, col)
        fig.suptitle(f"{study.name}: {col}", fontsize=10)
        fig.tight_layout()
        p = out_dir / f"{_safe(col)}.png"
        fig.savefig(p, dpi=110)
        plt.close(fig)
        paths.append(p)

    # One summary figure: a 2-D map per result for two varied parameters,
    # otherwise every result against every parameter.
    if len(names) == 2:
        k = len(cols)
        ncol = min(k, 2)
        nrow = (k + ncol - 1) // ncol
        fig, axes = plt.subplots(nrow, ncol, figsize=(5.6 * ncol, 4.2 * nrow), squeeze=False)
        for ax, col in zip(axes.flat, cols):
            _map(ax, fig, study, table, col)
            ax.set_title(col, fontsize=9)
        for ax in list(axes.flat)[k:]:
            ax.axis("off")
    else:
        fig, axes = plt.subplots(len(cols), len(names), figsize=(4.2 * len(names),
                                                                 3.0 * len(cols)), squeeze=False)
        for i, col in enumerate(cols):
            for j, pname in enumerate(names):
                _vs_parameter(axes[i][j], study, table, col, pname)
    title = study.name + (f"\n{study.question}" if study.question else "")
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    p = out_dir / "summary.png"
    fig.savefig(p, dpi=110)
    plt.close(fig)
    paths.append(p)
    return paths
