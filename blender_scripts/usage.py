"""Bad arguments of the headless scripts (batch.py, make_dataset.py): the exception their main()
reports with a message and exit code 2, and an argument parser that raises it."""

from __future__ import annotations

import argparse


class UsageError(Exception):
    """Bad input: reported with a message and exit code 2, without a traceback."""


class Parser(argparse.ArgumentParser):
    def error(self, message):  # argparse would print its usage and exit; main() says the message instead
        raise UsageError(message)
