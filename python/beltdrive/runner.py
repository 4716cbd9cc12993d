"""One run of the FMU, on whichever process executes it (a Dask worker or the
client). Each process extracts an FMU once (keyed by its SHA-256) and reuses
the extracted directory and the parsed model description for all its runs.
"""
from __future__ import annotations

import atexit
import os
import pathlib
import shutil
import socket
import tempfile
import threading
import time

from ctypes import byref

import numpy as np
from fmpy import calloc, extract, free, read_model_description
from fmpy.fmi1 import printLogMessage
from fmpy.fmi2 import (FMU2Slave, fmi2CallbackAllocateMemoryTYPE, fmi2CallbackFreeMemoryTYPE,
                       fmi2CallbackFunctions, fmi2CallbackLoggerTYPE)
from fmpy.logging import addLoggerProxy
from fmpy.simulation import simulate_fmu

from .study import compile_expression

_STATUS = {0: "OK", 1: "Warning", 2: "Discard", 3: "Error", 4: "Fatal", 5: "Pending"}

# FMPy's native logger proxy (fmpy.logging.addLoggerProxy) formats an FMU's
# message and hands it to ONE process-wide Python callback: the last one
# registered. A logger given to fmpy.simulation.instantiate_fmu is registered
# there and freed with its instance; after that, any FMU of the process that
# logs, through FMPy's default callbacks too, calls freed memory (a
# segmentation fault inside fmi2ExitInitializationMode when a parameter set
# is warned about). So the runs register one callback for the life of the
# process, which hands each message to the run of the calling thread, and
# outside a run to FMPy's own printLogMessage.
_SINK = threading.local()


def _dispatch(env, instance, status, category, message):
    logs = getattr(_SINK, "logs", None)
    if logs is None:
        printLogMessage(env, instance, status, category, message)
        return
    cat = category.decode(errors="replace") if category else ""
    msg = message.decode(errors="replace") if message else ""
    logs.append(f"[{_STATUS.get(status, status)}] {cat}: {msg}")


_CALLBACKS = fmi2CallbackFunctions()
_CALLBACKS.logger = fmi2CallbackLoggerTYPE(_dispatch)
_CALLBACKS.allocateMemory = fmi2CallbackAllocateMemoryTYPE(calloc)
_CALLBACKS.freeMemory = fmi2CallbackFreeMemoryTYPE(free)
addLoggerProxy(byref(_CALLBACKS))
_extracted: dict[str, tuple[str, object]] = {}
_lock = threading.Lock()


def _cleanup():
    for unzipdir, _ in _extracted.values():
        shutil.rmtree(unzipdir, ignore_errors=True)


atexit.register(_cleanup)


def locate_fmu(fmu_name: str) -> str:
    """Path of an FMU shipped with `Client.upload_file` (the worker's local
    directory), or `fmu_name` itself when it is a path that exists here."""
    if os.path.isfile(fmu_name):
        return fmu_name
    try:
        from distributed import get_worker
        path = os.path.join(get_worker().local_directory, os.path.basename(fmu_name))
    except ValueError:  # not on a worker
        path = fmu_name
    if not os.path.isfile(path):
        raise FileNotFoundError(f"FMU {fmu_name} was not shipped to this worker ({path})")
    return path


def extracted(fmu_name: str, sha256: str):
    """(unzip directory, model description) of the FMU, extracted once per process."""
    with _lock:
        if sha256 not in _extracted:
            path = locate_fmu(fmu_name)
            unzipdir = extract(path, unzipdir=tempfile.mkdtemp(prefix="beltdrive-sweep-"))
            _extracted[sha256] = (unzipdir, read_model_description(unzipdir))
        return _extracted[sha256]


def input_signals(inputs, stop_time, output_interval):
    """FMPy input array for the inputs given as expressions of time, sampled on
    the communication grid (FMPy applies the sample at each communication
    point). Constant inputs are start values instead; None if there are none."""
    exprs = [i for i in inputs if "expr" in i]
    if not exprs:
        return None
    n = int(round(stop_time / output_interval))
    t = np.arange(n + 1) * output_interval
    t[-1] = max(t[-1], stop_time)
    arr = np.zeros(len(t), dtype=[("time", np.float64)] + [(i["name"], np.float64) for i in exprs])
    arr["time"] = t
    for i in exprs:
        arr[i["name"]] = compile_expression(i["expr"], i["name"])(t)
    return arr


def start_values(spec):
    """Start values of a run: base set, fixed settings, the design point, constant inputs."""
    sv = dict(spec["start_values"])
    for i in spec["inputs"]:
        if "value" in i:
            sv[i["name"]] = i["value"]
    return sv


def window_stats(t, y, window, stats):
    """{stat: value} of y over t in [t0, t1] (closed; 1e-9 s slack for the grid's rounding)."""
    mask = (t >= window[0] - 1e-9) & (t <= window[1] + 1e-9)
    sel = y[mask]
    if sel.size == 0:
        return {s: float("nan") for s in stats}
    fn = {"mean": np.mean, "min": np.min, "max": np.max}
    return {s: float(fn[s](sel)) for s in stats}


def run_one(spec: dict, fmu_name: str) -> dict:
    """Simulate one parameter set; never raises for a failing simulation: a
    refused parameter set or a discarded step gives status "failed" and the
    FMU's log messages. Returns the row of the results table (and, with
    `series` asked for, the time series under the key "_series")."""
    logs = []
    row = {"index": spec["index"], "key": spec["key"], **spec["point"]}
    t_cpu, t_wall = time.thread_time(), time.perf_counter()
    status, message, res = "ok", "", None
    try:
        unzipdir, md = extracted(fmu_name, spec["fmu_sha256"])
        outputs = sorted({r[0] for r in spec["results"]} | set(spec["series"]))
        exp = md.defaultExperiment
        last = [float(exp.startTime) if exp is not None and exp.startTime else 0.0]

        def step_finished(t, recorder):
            # After a discarded step FMPy stays at the same time and would
            # retry it: time not advancing means a discard, stop there.
            moved = t != last[0]
            last[0] = t
            return moved

        fmu = FMU2Slave(guid=md.guid, unzipDirectory=unzipdir,
                        modelIdentifier=md.coSimulation.modelIdentifier, instanceName="run")
        fmu.instantiate(callbacks=_CALLBACKS)
        _SINK.logs = logs
        try:
            # Errors are always logged; warnings and discards (the reason a
            # step failed) only in these categories.
            fmu.setDebugLogging(True, ["logStatusWarning", "logStatusDiscard"])
            res = simulate_fmu(unzipdir, model_description=md, fmu_instance=fmu,
                               start_values=start_values(spec),
                               input=input_signals(spec["inputs"], spec["stop_time"],
                                                   spec["output_interval"]),
                               output=outputs, stop_time=spec["stop_time"],
                               output_interval=spec["output_interval"],
                               step_finished=step_finished)
        finally:
            fmu.freeInstance()
            _SINK.logs = None
        if not np.isclose(res["time"][-1], spec["stop_time"], rtol=0, atol=1e-9):
            status = "failed"
            message = f"stopped at t = {res['time'][-1]:.9g} s of {spec['stop_time']:g} s"
    except Exception as e:  # the run failed, the study goes on
        status, message = "failed", f"{type(e).__name__}: {e}"
        res = None
    cpu, wall = time.thread_time() - t_cpu, time.perf_counter() - t_wall
    fmu_log = " | ".join(m for m in logs if not m.startswith("[OK]"))
    message = " | ".join(m for m in (message, fmu_log) if m)

    for output, stats, window in spec["results"]:
        if res is not None and status == "ok":
            vals = window_stats(res["time"], res[output], window, stats)
        else:
            vals = {s: float("nan") for s in stats}
        for s in stats:
            row[f"{s}({output})"] = vals[s]
    row.update(status=status, message=message, cpu_time_s=cpu, wall_time_s=wall,
               worker=f"{socket.gethostname()}:{os.getpid()}")
    if spec["series"] and res is not None:
        row["_series"] = {n: np.array(res[n]) for n in ["time", *spec["series"]]}
    return row


def sha256_file(path) -> str:
    import hashlib
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def fmu_upload_name(path, sha256: str) -> str:
    """File name under which an FMU is shipped: its content hash makes a
    rebuilt FMU a new file on the workers."""
    return f"{pathlib.Path(path).stem}-{sha256[:16]}.fmu"
