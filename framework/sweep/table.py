"""The table of a sweep: ``sweep.csv`` (and ``sweep.nc`` with xarray), and the text the command prints."""
import csv
import json
import math
import os
import warnings

from .. import io
from .points import BOOKKEEPING, OUTPUT_PREFIX

TABLE_FILE = "sweep.csv"
NETCDF_FILE = "sweep.nc"
#: The statuses of a row: run now, read back from its file, run again because its file was damaged, failed.
STATUS = ("done", "skipped", "recomputed", "failed")
#: Outputs the command prints for each point (all are in the CSV file).
SHOWN = ("final.load", "final.contact_radius", "final.max_pressure", "final.friction_coefficient", "wall_time")


def cell(value):
    """A value as the CSV file writes it: floats to the bit, lists and tables as JSON, None empty."""
    if value is None:
        return ""
    if isinstance(value, float):
        return repr(value)
    if isinstance(value, (list, dict)):
        return json.dumps(value)
    return str(value)


def write_table(rows, path):
    """Write ``rows`` (dicts with the same keys) to the CSV file ``path`` (temporary name, then rename)."""
    columns = list(rows[0]) if rows else list(BOOKKEEPING)
    temporary = io.temporary(path)
    with open(temporary, "w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(columns)
        for row in rows:
            writer.writerow([cell(row.get(key)) for key in columns])
    os.replace(temporary, path)


def write_netcdf(rows, path):
    """The table as NetCDF, when ``xarray`` is importable (it is not a dependency); a failure only warns."""
    try:
        import xarray
    except ImportError:
        return
    try:
        variables = {}
        for key in rows[0]:
            values = [row[key] for row in rows]
            if all(isinstance(v, (int, float)) and not isinstance(v, bool) or v is None for v in values):
                values = [math.nan if v is None else float(v) for v in values]
            else:
                values = ["" if v is None else cell(v) for v in values]
            variables[key] = ("point", values)
        xarray.Dataset(variables).to_netcdf(path)
    except Exception as exc:  # noqa: BLE001 - the CSV table is the reference output
        warnings.warn(f"{path} not written: {exc}", stacklevel=3)


def format_table(rows):
    """The table as aligned text: the parameters, the status and a few outputs (or the error)."""
    if not rows:
        return ""
    keys = [k for k in rows[0] if k not in BOOKKEEPING and not k.startswith(OUTPUT_PREFIX)]
    lines = [["#"] + keys + ["status"] + list(SHOWN)]
    for row in rows:
        cells = [str(row["index"])] + [f"{row[k]:.6g}" if isinstance(row[k], float) else cell(row[k])
                                       for k in keys] + [row["status"]]
        if row["status"] == "failed":
            cells.append(row["error"])
        else:
            cells += ["" if row.get(k) is None else f"{row[k]:.4g}" for k in SHOWN]
        lines.append(cells)
    width = {}
    for line in lines:
        for i, text in enumerate(line[:-1]):
            width[i] = max(width.get(i, 0), len(text))
    return "\n".join("  ".join([text.ljust(width[i]) for i, text in enumerate(line[:-1])] + [line[-1]]).rstrip()
                     for line in lines)


def count(rows):
    """``{status: number of rows}`` for every status of :data:`STATUS`."""
    return {status: sum(row["status"] == status for row in rows) for status in STATUS}
