"""BeltDrive parameter studies: design-of-experiments sweeps of BeltDrive.fmu
on Dask distributed (`python -m beltdrive.sweep STUDY.toml`, docs/sweeps.md)."""
from .study import StudyError, load  # noqa: F401

__all__ = ["StudyError", "load", "run_study"]


def run_study(*args, **kwargs):
    """See beltdrive.sweep.run_study."""
    from .sweep import run_study as _run
    return _run(*args, **kwargs)
