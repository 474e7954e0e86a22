"""Errors of the testbench."""

from __future__ import annotations


class WiringError(ValueError):
    """The model does not provide what an axis needs; the message says what and what would fit."""
