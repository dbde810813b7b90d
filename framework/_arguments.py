"""Command-line parsing shared by the commands: every usage error is one line ``error: ...`` and a hint."""
import argparse


class Parser(argparse.ArgumentParser):
    """argparse whose usage errors are one line ``error: ...`` (exit code 2), like every other bad input.

    The line ends with the hint ``(see PROG -h)``, where the usage and every
    option are listed; argparse's own multi-line usage is not printed.
    """

    def error(self, message):
        self.exit(2, f"error: {message} (see {self.prog} -h)\n")


def integer(minimum):
    """An argparse type: an integer >= ``minimum``."""
    def parse(text):
        try:
            value = int(text)
        except ValueError:
            value = None
        if value is None or value < minimum:
            raise argparse.ArgumentTypeError(f"expected an integer >= {minimum}, got {text!r}")
        return value
    return parse
