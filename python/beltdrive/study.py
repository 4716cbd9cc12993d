"""A parameter study read from a TOML file: the FMU, a base parameter set, inputs,
the design (which parameter sets to run) and the results to keep.

Everything here runs on the client; nothing needs a Dask worker. The run
specifications it produces (:class:`Run`) are plain dictionaries that the
workers execute with :func:`beltdrive.runner.run_one`.
"""
from __future__ import annotations

import ast
import hashlib
import itertools
import json
import math
import pathlib
import tomllib
from dataclasses import dataclass, field

import numpy as np
from fmpy import read_model_description
from fmpy.ssp.ssd import read_ssv


class StudyError(ValueError):
    """The study file is wrong; the message names the entry and how to fix it."""


_CONVERT = {
    "Real": float,
    "Integer": int,
    "Boolean": lambda s: s.strip() in ("true", "1"),  # xs:boolean
}

# Names an input expression may use besides `t` (time in s).
_EXPR_NAMES = {
    "pi": math.pi, "e": math.e,
    "sin": np.sin, "cos": np.cos, "tan": np.tan, "exp": np.exp, "log": np.log,
    "sqrt": np.sqrt, "abs": np.abs, "minimum": np.minimum, "maximum": np.maximum,
    "clip": np.clip, "where": np.where, "tanh": np.tanh, "sign": np.sign,
}
_EXPR_NODES = (ast.Expression, ast.BinOp, ast.UnaryOp, ast.Call, ast.Name, ast.Load,
               ast.Constant, ast.Compare, ast.operator, ast.unaryop, ast.cmpop)

DESIGNS = ("grid", "list", "lhs", "random")
STATS = ("mean", "min", "max")


def variable_unit(var) -> str:
    """Unit of an FMU variable as its model description gives it ("" for none)."""
    if var.unit:
        return var.unit
    if var.declaredType is not None and var.declaredType.unit:
        return var.declaredType.unit
    return ""


def _check_unit(md_vars, name, unit, where):
    var = md_vars.get(name)
    if var is None:
        raise StudyError(f"{where}: the FMU has no variable {name!r} (see `fmpy info` or "
                         "modelDescription/modelDescription.xml for the names)")
    expected = variable_unit(var)
    if var.type in ("Integer", "Boolean", "Enumeration"):
        if unit not in (None, "", "1"):
            raise StudyError(f"{where}: {name} is a {var.type} without a unit; "
                             f"remove unit = {unit!r}")
        return var
    if unit is None:
        raise StudyError(f"{where}: give the unit of {name} (unit = {expected!r})")
    if unit != expected:
        raise StudyError(f"{where}: {name} is in {expected!r}, the study gives {unit!r}; "
                         f"convert the values to {expected} and write unit = {expected!r}")
    return var


def compile_expression(expr: str, where: str):
    """A function of time (numpy array in s) from an expression such as
    ``"3 + 0.5*sin(2*pi*20*t)"``. Only arithmetic, comparisons, `t` and the
    names in _EXPR_NAMES are allowed."""
    try:
        tree = ast.parse(expr, mode="eval")
    except SyntaxError as e:
        raise StudyError(f"{where}: expression {expr!r} does not parse: {e.msg}") from None
    for node in ast.walk(tree):
        if not isinstance(node, _EXPR_NODES):
            raise StudyError(f"{where}: {type(node).__name__} not allowed in {expr!r}")
        if isinstance(node, ast.Name) and node.id != "t" and node.id not in _EXPR_NAMES:
            raise StudyError(f"{where}: unknown name {node.id!r} in {expr!r}; use t and "
                             + ", ".join(sorted(_EXPR_NAMES)))
    code = compile(tree, where, "eval")

    def f(t):
        t = np.asarray(t, dtype=float)
        return np.broadcast_to(np.asarray(eval(code, {"__builtins__": {}}, {**_EXPR_NAMES, "t": t}),
                                          dtype=float), t.shape).copy()
    return f


@dataclass
class Parameter:
    name: str
    unit: str | None
    type: str
    values: list | None = None
    low: float | None = None
    high: float | None = None


@dataclass
class Result:
    output: str
    stats: list
    window: tuple

    def columns(self):
        return [f"{s}({self.output})" for s in self.stats]


@dataclass
class Study:
    path: pathlib.Path
    name: str
    question: str
    fmu: pathlib.Path
    base: pathlib.Path | None
    base_values: dict
    fixed: dict
    inputs: list            # [{"name", "value"} | {"name", "expr"}]
    parameters: list        # [Parameter]
    design: str
    samples: int | None
    seed: int | None
    stop_time: float
    output_interval: float
    results: list           # [Result]
    series: list
    out_dir: pathlib.Path
    plots: list = field(default_factory=list)

    # ---- design ----------------------------------------------------------
    def points(self) -> list[dict]:
        """The parameter sets of the design, in a fixed order: a list of
        {parameter name: value}."""
        ps = self.parameters
        if self.design == "grid":
            combos = itertools.product(*[p.values for p in ps])
            return [{p.name: v for p, v in zip(ps, c)} for c in combos]
        if self.design == "list":
            return [{p.name: p.values[i] for p in ps} for i in range(len(ps[0].values))]
        if self.design == "lhs":
            from scipy.stats import qmc
            u = qmc.LatinHypercube(d=len(ps), seed=np.random.default_rng(self.seed)).random(
                self.samples)
        else:
            u = np.random.default_rng(self.seed).random((self.samples, len(ps)))
        out = []
        for row in u:
            pt = {}
            for p, x in zip(ps, row):
                v = p.low + float(x) * (p.high - p.low)
                pt[p.name] = int(round(v)) if p.type == "Integer" else v
            out.append(pt)
        return out

    # ---- runs ------------------------------------------------------------
    def runs(self, fmu_sha256: str) -> list[dict]:
        """One run specification per design point, with the key that
        identifies its result in the store."""
        result_spec = [[r.output, list(r.stats), list(r.window)] for r in self.results]
        runs = []
        for i, pt in enumerate(self.points()):
            start = {**self.base_values, **self.fixed, **pt}
            spec = {
                "fmu_sha256": fmu_sha256,
                "start_values": start,
                "inputs": self.inputs,
                "stop_time": self.stop_time,
                "output_interval": self.output_interval,
                "results": result_spec,
                "series": list(self.series),
            }
            key = run_key(spec)
            runs.append({"index": i, "key": key, "point": pt, **spec})
        return runs


def run_key(spec: dict) -> str:
    """SHA-256 of everything that determines a run's result (FMU binary,
    all start values, inputs, stop time, sampling, results asked for)."""
    text = json.dumps(spec, sort_keys=True, separators=(",", ":"), default=repr)
    return hashlib.sha256(text.encode()).hexdigest()[:32]


def ssv_values(path) -> dict:
    """{variable name: typed value} of an .ssv file (schema-validated by FMPy)."""
    return {p.name: _CONVERT[p.type](p.value) for p in read_ssv(str(path)).parameters}


def _typed(var, value, where):
    if var.type == "Real":
        if not isinstance(value, (int, float)) or isinstance(value, bool):
            raise StudyError(f"{where}: {var.name} takes a number, got {value!r}")
        return float(value)
    if var.type in ("Integer", "Enumeration"):
        if not isinstance(value, int) or isinstance(value, bool):
            raise StudyError(f"{where}: {var.name} takes an integer, got {value!r}")
        return int(value)
    if var.type == "Boolean":
        if not isinstance(value, bool):
            raise StudyError(f"{where}: {var.name} takes true or false, got {value!r}")
        return value
    raise StudyError(f"{where}: {var.name} is a {var.type}; only Real, Integer and Boolean "
                     "variables can be set")


def load(path, fmu=None, out_dir=None) -> Study:
    """Read and check a study file. `fmu` and `out_dir` override the file's."""
    path = pathlib.Path(path).resolve()
    try:
        doc = tomllib.loads(path.read_text())
    except tomllib.TOMLDecodeError as e:
        raise StudyError(f"{path}: {e}") from None
    here = path.parent
    st = doc.get("study", {})
    for k in ("fmu", "stop_time"):
        if k not in st:
            raise StudyError(f"{path}: [study] needs {k} = ...")
    fmu_path = pathlib.Path(fmu) if fmu else (here / st["fmu"])
    if not fmu_path.is_file():
        raise StudyError(f"[study] fmu: {fmu_path} does not exist (build it: cargo xtask fmu)")
    md = read_model_description(str(fmu_path))
    md_vars = {v.name: v for v in md.modelVariables}

    base = here / st["base"] if "base" in st else None
    base_values = ssv_values(base) if base else {}
    for name in base_values:
        if name not in md_vars:
            raise StudyError(f"[study] base {base}: the FMU has no variable {name!r}")

    fixed = {}
    for key, value in doc.get("solver", {}).items():
        name = f"solver.{key}"
        if name not in md_vars:
            raise StudyError(f"[solver] {key}: the FMU has no variable {name!r}; its solver "
                             "settings are " + ", ".join(n[7:] for n in md_vars
                                                        if n.startswith("solver.")
                                                        and md_vars[n].causality == "parameter"))
        fixed[name] = _typed(md_vars[name], value, f"[solver] {key}")
    for i, fx in enumerate(doc.get("fixed", [])):
        where = f"[[fixed]] #{i + 1}"
        var = _check_unit(md_vars, fx.get("name"), fx.get("unit"), where)
        fixed[var.name] = _typed(var, fx.get("value"), where)

    stop_time = float(st["stop_time"])
    if not stop_time > 0:
        raise StudyError(f"[study] stop_time must be > 0 s, got {stop_time}")
    output_interval = float(st.get("output_interval", 1e-3))
    if not 0 < output_interval <= stop_time:
        raise StudyError(f"[study] output_interval must be in (0, stop_time], got {output_interval}")

    inputs = []
    for i, inp in enumerate(doc.get("input", [])):
        where = f"[[input]] #{i + 1}"
        var = _check_unit(md_vars, inp.get("name"), inp.get("unit"), where)
        if var.causality != "input":
            raise StudyError(f"{where}: {var.name} is a {var.causality}, not an input; set "
                             "parameters under [[fixed]] or vary them under [[parameter]]")
        if ("value" in inp) == ("expr" in inp):
            raise StudyError(f"{where}: give either value = NUMBER or expr = \"... t ...\"")
        if "expr" in inp:
            f = compile_expression(inp["expr"], where)
            f(np.linspace(0.0, stop_time, 3))  # evaluate once: catches bad calls early
            inputs.append({"name": var.name, "expr": inp["expr"]})
        else:
            inputs.append({"name": var.name, "value": _typed(var, inp["value"], where)})

    de = doc.get("design", {})
    design = de.get("type", "grid")
    if design not in DESIGNS:
        raise StudyError(f"[design] type = {design!r}: use one of {', '.join(DESIGNS)}")
    samples = de.get("samples")
    seed = de.get("seed")
    if design in ("lhs", "random"):
        if not isinstance(samples, int) or samples < 1:
            raise StudyError(f"[design] type = {design!r} needs samples = N (N >= 1)")
        if not isinstance(seed, int):
            raise StudyError(f"[design] type = {design!r} needs seed = INTEGER so that the "
                             "study is repeatable")

    params = []
    for i, p in enumerate(doc.get("parameter", [])):
        where = f"[[parameter]] #{i + 1} ({p.get('name')})"
        var = _check_unit(md_vars, p.get("name"), p.get("unit"), where)
        if var.causality not in ("parameter", "input"):
            raise StudyError(f"{where}: {var.name} is an {var.causality}; only parameters and "
                             "inputs (held constant) can be varied")
        if any(q.name == var.name for q in params):
            raise StudyError(f"{where}: {var.name} is varied twice")
        par = Parameter(var.name, p.get("unit"), var.type)
        if design in ("grid", "list"):
            if not isinstance(p.get("values"), list) or not p["values"]:
                raise StudyError(f"{where}: design {design!r} needs values = [...]")
            par.values = [_typed(var, v, where) for v in p["values"]]
        else:
            if "low" not in p or "high" not in p:
                raise StudyError(f"{where}: design {design!r} needs low = ... and high = ...")
            if var.type not in ("Real", "Integer"):
                raise StudyError(f"{where}: design {design!r} samples Real or Integer variables")
            par.low, par.high = float(p["low"]), float(p["high"])
            if not par.low < par.high:
                raise StudyError(f"{where}: low must be < high")
        params.append(par)
    if not params:
        raise StudyError(f"{path}: no [[parameter]] to vary")
    if design == "list" and len({len(p.values) for p in params}) != 1:
        raise StudyError("[design] type = 'list' needs the same number of values for every "
                         "[[parameter]] (run i takes the i-th value of each)")

    results = []
    for i, r in enumerate(doc.get("result", [])):
        where = f"[[result]] #{i + 1}"
        name = r.get("output")
        if name not in md_vars:
            raise StudyError(f"{where}: the FMU has no variable {name!r}")
        stats = r.get("stats", list(STATS))
        bad = [s for s in stats if s not in STATS]
        if bad:
            raise StudyError(f"{where}: stats {bad} unknown; use {', '.join(STATS)}")
        window = r.get("window", [0.0, stop_time])
        if len(window) != 2 or not 0 <= window[0] <= window[1] <= stop_time:
            raise StudyError(f"{where}: window = [t0, t1] with 0 <= t0 <= t1 <= stop_time "
                             f"({stop_time} s), got {window}")
        results.append(Result(name, list(stats), (float(window[0]), float(window[1]))))
    if not results:
        raise StudyError(f"{path}: no [[result]] to keep")
    series = doc.get("series", {}).get("outputs", [])
    for name in series:
        if name not in md_vars:
            raise StudyError(f"[series] outputs: the FMU has no variable {name!r}")

    out = pathlib.Path(out_dir) if out_dir else here / st.get("out", path.stem + ".out")
    return Study(path=path, name=st.get("name", path.stem), question=st.get("question", ""),
                 fmu=fmu_path.resolve(), base=base, base_values=base_values, fixed=fixed,
                 inputs=inputs, parameters=params, design=design, samples=samples, seed=seed,
                 stop_time=stop_time, output_interval=output_interval, results=results,
                 series=list(series), out_dir=out.resolve(), plots=doc.get("plot", []))
