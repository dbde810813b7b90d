"""Parametric studies on Dask distributed: one simulation per point, one file per point.

    rows = sweep(build, {"radius": [5e-3, 1e-2], "young": [1e9, 2e9]}, folder="study")

runs ``build(**point).run()`` for every point of the Cartesian product on a
Dask cluster, saves each result to ``study/point_<index>_<hash>.h5`` and the
last step's scalars of every point to ``study/sweep.csv`` (the parameters under
their own names, the outputs as ``final.<series>``). A rerun skips the points
whose file is there, and runs again those whose file is damaged, so a killed
sweep is finished by running it again.

Scenario sweeps: :class:`ScenarioBuilder` turns a scenario file (or its
tables) into a picklable ``build`` whose keyword arguments are dotted keys
(``"material.young"``, ``"schedule.load.value"``), and :func:`read_sweep`
reads a sweep file (see :mod:`framework.sweep.reader`).

Where each piece is:

- :mod:`~framework.sweep.points`: the points (:func:`expand`), their hash and file names, the reserved columns;
- :mod:`~framework.sweep.worker`: one point as a worker runs it (:func:`run_point`) or reads it back;
- :mod:`~framework.sweep.cluster`: :func:`sweep` itself, on a local cluster or a scheduler's;
- :mod:`~framework.sweep.table`: ``sweep.csv`` (:func:`write_table`), ``sweep.nc`` and the printed table;
- :mod:`~framework.sweep.builder`: :class:`ScenarioBuilder`;
- :mod:`~framework.sweep.reader`: sweep files (:func:`read_sweep`) and the check of every point;
- :mod:`~framework.sweep.command`: ``python -m framework sweep SWEEP.toml [--check] [--scheduler ADDRESS]
  [--folder DIR] [--quiet]`` (:func:`main`).

Dask and distributed are imported only in :mod:`~framework.sweep.cluster`;
without them :func:`sweep` raises :class:`MissingExtraError` naming
``pip install 'viscocontact[cluster]'``.
"""
from ..extras import MissingExtraError
from .builder import ScenarioBuilder
from .cluster import CONNECT_TIMEOUT, DEFAULT_FOLDER, EXTRA, connect, import_distributed, sweep
from .command import main
from .points import BOOKKEEPING, OUTPUT_PREFIX, expand, point_file, point_hash, series_names
from .reader import SWEEP_KEYS, check_points, is_sweep, read_sweep
from .table import NETCDF_FILE, SHOWN, STATUS, TABLE_FILE, format_table, write_table
from .worker import PARTIAL, read_point, remove_partials, run_point

__all__ = ["sweep", "ScenarioBuilder", "read_sweep", "check_points", "is_sweep", "expand", "point_file",
           "point_hash", "series_names", "run_point", "read_point", "remove_partials", "write_table",
           "format_table", "connect", "import_distributed", "main", "MissingExtraError", "BOOKKEEPING",
           "OUTPUT_PREFIX", "STATUS", "TABLE_FILE", "NETCDF_FILE", "SHOWN", "PARTIAL", "SWEEP_KEYS", "EXTRA",
           "DEFAULT_FOLDER", "CONNECT_TIMEOUT"]
