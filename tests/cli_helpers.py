"""What the command-line tests share: running ``python -m framework`` in this process, the one-line error
they expect, and a small scenario that runs (imported by the test files, not collected itself)."""
import re

#: A scenario that runs in a fraction of a second: a sphere on an elastic half-space, one load.
GOOD = """
[grid]
shape = [16, 16]
size = [1e-3, 1e-3]
[material]
type = "Elastic"
young = 1e9
poisson = 0.3
[indenter]
type = "Sphere"
radius = 5e-3
[schedule]
load = 1.0
"""


def cli(capsys, *args):
    """Exit code, stdout and stderr of ``python -m framework ARGS`` in this process."""
    from framework.__main__ import main
    try:
        code = main(list(args))
    except SystemExit as exc:  # argparse
        code = exc.code
    captured = capsys.readouterr()
    return code, captured.out, captured.err


def one_error(code, err, pattern):
    """The command failed with exit code 2 and one line ``error: ...`` matching ``pattern``, no traceback."""
    assert code == 2 and "Traceback" not in err, err
    assert len(err.strip().splitlines()) == 1 and err.startswith("error: "), err
    assert re.search(pattern, err), err
