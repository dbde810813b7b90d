"""Command line: ``python -m framework demo [--out DIR] [--cells N]``."""
import argparse
import sys

from .errors import FrameworkError


def main(argv=None):
    parser = argparse.ArgumentParser(prog="python -m framework", description=__doc__)
    commands = parser.add_subparsers(dest="command", required=True)
    demo = commands.add_parser("demo", help="run the default scenario and write its outputs")
    demo.add_argument("--out", default="out", help="output folder (default: out)")
    demo.add_argument("--cells", type=int, default=129, help="cells per side of the surface grid (default: 129)")
    args = parser.parse_args(argv)
    try:
        if args.command == "demo":
            from .demo import main as run_demo
            run_demo(args.out, args.cells)
    except FrameworkError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
