"""Run a parameter study of BeltDrive.fmu on Dask distributed.

    python -m beltdrive.sweep STUDY.toml [--scheduler tcp://HOST:8786] [--workers N]

(`cargo xtask sweep -- STUDY.toml ...` builds the FMU and the venv, then runs
this.) Without --scheduler a LocalCluster with one single-threaded worker
process per core is started. The FMU (and this package) are shipped to the
workers; each worker extracts the FMU once. Every finished run is written at
once to OUT/runs/KEY.parquet, KEY being a hash of everything that determines
the run, so a study interrupted and started again runs only what is missing.
At the end the parts are merged into OUT/results.parquet and the plots are
drawn.
"""
from __future__ import annotations

import argparse
import io
import json
import os
import pathlib
import shutil
import sys
import tempfile
import time
import zipfile

import pandas as pd

from . import runner
from .study import StudyError, load

PACKAGE_DIR = pathlib.Path(__file__).resolve().parent


def _write_atomic(df: pd.DataFrame, path: pathlib.Path):
    tmp = path.with_name(path.name + ".tmp")
    df.to_parquet(tmp, index=False)
    os.replace(tmp, path)


def _package_zip(dest: pathlib.Path) -> pathlib.Path:
    """This package as a zip for Client.upload_file (workers on other machines
    then need only the pinned requirements, not this repository)."""
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w") as z:
        for f in sorted(PACKAGE_DIR.glob("*.py")):
            z.write(f, f"beltdrive/{f.name}")
    path = dest / "beltdrive_pkg.zip"
    path.write_bytes(buf.getvalue())
    return path


def _client(scheduler, workers):
    from distributed import Client, LocalCluster
    if scheduler:
        return Client(scheduler), None
    n = workers or os.cpu_count() or 1
    cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                           dashboard_address=None)
    return Client(cluster), cluster


def _progress(total):
    try:
        from tqdm import tqdm
        return tqdm(total=total, unit="run", file=sys.stderr, smoothing=0.1)
    except ImportError:  # pragma: no cover
        return None


def run_study(study_path, scheduler=None, workers=None, out_dir=None, fmu=None,
              retry_failed=False, progress=True, log=print):
    """Run the study; returns a summary dict (executed and skipped run keys,
    the results table path)."""
    study = load(study_path, fmu=fmu, out_dir=out_dir)
    out = study.out_dir
    runs_dir, series_dir = out / "runs", out / "series"
    runs_dir.mkdir(parents=True, exist_ok=True)
    if study.series:
        series_dir.mkdir(exist_ok=True)
    sha = runner.sha256_file(study.fmu)
    runs = study.runs(sha)
    if len({r["key"] for r in runs}) != len(runs):
        raise StudyError(f"{study.path}: the design repeats a parameter set")

    done = {p.stem for p in runs_dir.glob("*.parquet")}
    if retry_failed and done:
        for key in list(done):
            if pd.read_parquet(runs_dir / f"{key}.parquet")["status"].iloc[0] != "ok":
                done.discard(key)
    todo = [r for r in runs if r["key"] not in done]
    log(f"{study.name}: {len(runs)} runs, {len(runs) - len(todo)} already in {runs_dir}, "
        f"{len(todo)} to run")

    executed, lost = [], []
    t0 = time.perf_counter()
    n_workers, runs_wall = 0, 0.0
    if todo:
        from distributed import as_completed
        client, cluster = _client(scheduler, workers)
        tmp = pathlib.Path(tempfile.mkdtemp(prefix="beltdrive-ship-"))
        try:
            n_workers = len(client.scheduler_info()["workers"])
            log(f"Dask scheduler {client.scheduler.address}, {n_workers} workers")
            fmu_name = runner.fmu_upload_name(study.fmu, sha)
            shutil.copyfile(study.fmu, tmp / fmu_name)
            # Worker plugins: workers that join later get them too. A remote
            # scheduler unpickles the tasks, so it gets the package as well;
            # a local cluster's scheduler is this process, which has it.
            from distributed.diagnostics.plugin import SchedulerUploadFile, UploadFile
            pkg = str(_package_zip(tmp))
            if cluster is None:
                client.register_plugin(SchedulerUploadFile(pkg), name="beltdrive-package")
            client.register_plugin(UploadFile(pkg), name="beltdrive-package")
            client.register_plugin(UploadFile(str(tmp / fmu_name), load=False),
                                   name=f"beltdrive-fmu-{sha[:16]}")
            t_runs = time.perf_counter()
            futures = client.map(runner.run_one, todo, fmu_name=fmu_name,
                                 key=[f"beltdrive-run-{r['key']}" for r in todo], pure=False)
            bar = _progress(len(todo)) if progress else None
            for fut in as_completed(futures):
                try:
                    row = fut.result()
                except Exception as e:  # worker lost etc.: not stored, retried next time
                    lost.append(f"{fut.key}: {type(e).__name__}: {e}")
                    continue
                finally:
                    if bar is not None:
                        bar.update()
                    fut.release()
                series = row.pop("_series", None)
                if series is not None:
                    _write_atomic(pd.DataFrame(series), series_dir / f"{row['key']}.parquet")
                _write_atomic(pd.DataFrame([row]), runs_dir / f"{row['key']}.parquet")
                executed.append(row["key"])
            if bar is not None:
                bar.close()
            runs_wall = time.perf_counter() - t_runs
        finally:
            client.close()
            if cluster is not None:
                cluster.close()
            shutil.rmtree(tmp, ignore_errors=True)
    wall = time.perf_counter() - t0

    table = merge(study, runs)
    results = out / "results.parquet"
    _write_atomic(table, results)
    summary = {
        "study": str(study.path), "runs": len(runs), "executed": executed,
        "skipped": len(runs) - len(todo), "lost": lost, "workers": n_workers,
        "wall_time_s": wall, "runs_wall_time_s": runs_wall, "results": str(results),
        "failed": int((table["status"] != "ok").sum()) if len(table) else 0,
    }
    (out / "last_session.json").write_text(json.dumps(summary, indent=1))
    log(f"executed {len(executed)} runs on {n_workers} workers in {wall:.1f} s, of which "
        f"{runs_wall:.1f} s from the first submission to the last result"
        + (f" ({len(executed) / runs_wall * 60:.1f} runs/min)" if executed and runs_wall > 0
           else "")
        + f"; {summary['failed']} failed rows; table {results}")
    for msg in lost:
        log(f"lost (will be rerun): {msg}")
    if len(table):
        from .plots import plot_study
        for p in plot_study(study, table, out / "plots"):
            log(f"plot {p}")
    return summary


def merge(study, runs) -> pd.DataFrame:
    """The finished runs of the current design, in design order."""
    parts = []
    for r in runs:
        p = study.out_dir / "runs" / f"{r['key']}.parquet"
        if p.exists():
            df = pd.read_parquet(p)
            df["index"] = r["index"]
            parts.append(df)
    if not parts:
        return pd.DataFrame()
    return pd.concat(parts, ignore_index=True).sort_values("index").reset_index(drop=True)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("study", type=pathlib.Path)
    ap.add_argument("--scheduler", help="address of a running Dask scheduler, "
                    "e.g. tcp://HOST:8786 (default: a local cluster)")
    ap.add_argument("--workers", type=int, help="local cluster size (default: one per core)")
    ap.add_argument("--out", type=pathlib.Path, help="output directory (default: the study's)")
    ap.add_argument("--fmu", type=pathlib.Path, help="FMU to use instead of the study's")
    ap.add_argument("--retry-failed", action="store_true",
                    help="run again the parameter sets whose stored row failed")
    ap.add_argument("--figure", type=pathlib.Path,
                    help="also write the study's summary figure to this path")
    ap.add_argument("--no-progress", action="store_true")
    a = ap.parse_args(argv)
    if a.scheduler and a.workers:
        ap.error("--workers sets the size of a local cluster; with --scheduler the "
                 "cluster is whatever workers joined that scheduler")
    try:
        s = run_study(a.study, scheduler=a.scheduler, workers=a.workers, out_dir=a.out,
                      fmu=a.fmu, retry_failed=a.retry_failed, progress=not a.no_progress)
    except StudyError as e:
        print(f"study error: {e}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("interrupted: the finished runs are stored; run the same command again to "
              "resume", file=sys.stderr)
        return 130
    if a.figure:
        summary = pathlib.Path(s["results"]).parent / "plots" / "summary.png"
        a.figure.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(summary, a.figure)
        print(f"figure {a.figure}")
    return 0 if not s["lost"] else 1


if __name__ == "__main__":
    sys.exit(main())
