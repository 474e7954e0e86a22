"""A process that parses pieces of a source for :mod:`plc.st.frontend.parse` (run as
``python -m plc.st.frontend.worker``): it reads a pickled list of (text, file name, first line,
first character, cache name) on stdin, parses each and keeps it in the cache, and writes a
pickled list of its trees on stdout, up to the first syntax error (its message in the tree's
place)."""

from __future__ import annotations

__all__ = ["main"]

import pickle
import sys
from typing import Any


def main() -> None:
    """Parse the pieces on stdin; their trees (up to the first error's message) to stdout."""
    from plc.st.errors import STError
    from plc.st.frontend.parse import parse_kept

    work = pickle.load(sys.stdin.buffer)
    result: list[Any] = []
    for piece in work:
        try:
            result.append(parse_kept(*piece))
        except STError as error:
            result.append(str(error))
            break
    pickle.dump(result, sys.stdout.buffer, protocol=pickle.HIGHEST_PROTOCOL)


if __name__ == "__main__":
    main()
