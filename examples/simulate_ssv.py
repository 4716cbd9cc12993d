"""Simulate BeltDrive.fmu with a parameter set from an SSP parameter-value file
(.ssv, SSP 1.0) through FMPy.

    .venv/bin/python examples/simulate_ssv.py parameters/kubas2014-section3.ssv \
        --stop-time 0.2 --output-file section3.csv

FMPy reads and schema-validates the .ssv (fmpy.ssp.ssd.read_ssv); its values
become the FMU's start values. Units: every Real in the .ssv carries the unit
of the FMU variable (the test tests/python/test_parameter_sets.py checks it),
so no conversion is needed.
"""
import argparse
import pathlib

from fmpy import simulate_fmu, write_csv
from fmpy.ssp.ssd import read_ssv

ROOT = pathlib.Path(__file__).resolve().parents[1]
FMU = ROOT / "dist" / "BeltDrive.fmu"
OUTPUTS = ["pulley[1].omega", "pulley[2].omega", "span[1].tension", "span[2].tension",
           "belt.minTension", "belt.maxTension"]

_CONVERT = {
    "Real": float,
    "Integer": int,
    "Boolean": lambda s: s.strip() in ("true", "1"),  # xs:boolean
}


def start_values(ssv_path):
    """{variable name: typed value} of an .ssv file (schema-validated)."""
    parameter_set = read_ssv(str(ssv_path))
    return {p.name: _CONVERT[p.type](p.value) for p in parameter_set.parameters}


def simulate(ssv_path, stop_time, output_interval=1e-3, output=None, fmu=FMU):
    return simulate_fmu(str(fmu), stop_time=stop_time, output_interval=output_interval,
                        start_values=start_values(ssv_path), output=output)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("ssv", type=pathlib.Path)
    ap.add_argument("--stop-time", type=float, default=0.1)
    ap.add_argument("--output-interval", type=float, default=1e-3)
    ap.add_argument("--output-file", type=pathlib.Path)
    ap.add_argument("--fmu", type=pathlib.Path, default=FMU)
    args = ap.parse_args()
    res = simulate(args.ssv, args.stop_time, args.output_interval, OUTPUTS, args.fmu)
    for name in OUTPUTS:
        print(f"{name:18s} {res[name][-1]:12.5g}  (t = {res['time'][-1]:g} s)")
    if args.output_file:
        write_csv(str(args.output_file), res)
        print(f"wrote {args.output_file}")


if __name__ == "__main__":
    main()
