"""Reading the JSON files a user gives (a log folder's ``meta.json``, a calibration, a parameter
file): any content that is not JSON text is a ValueError naming the file and what is wrong."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

from ._paths import check_file


def read_json(path: Path) -> Any:
    """The JSON value of the file ``path``.

    Raises:
        ValueError: naming ``path``: not a regular file (a named pipe would be waited on for
            ever), not UTF-8, not JSON (with the line and column), nested deeper than Python's
            JSON parser goes (it raises RecursionError there), or a key given twice in an object.
        OSError: the file cannot be read.
    """
    check_file(path)
    try:
        return json.loads(path.read_text(encoding="utf-8"), object_pairs_hook=_once_each)
    except _KeyTwice as e:
        raise ValueError(f"{path}: the key {e.args[0]!r} is given twice in one object; keep one") from None
    except json.JSONDecodeError as e:
        # "Expecting value" alone does not say the file is not JSON at all (a CSV given as --calibration)
        raise ValueError(f"{path}: not valid JSON: line {e.lineno} column {e.colno}: {e.msg}") from None
    except UnicodeDecodeError as e:
        raise ValueError(f"{path}: not UTF-8 text (at byte offset {e.start}: {e.reason}); save it as UTF-8") from None
    except RecursionError:
        raise ValueError(f"{path}: JSON nested too deeply to read (arrays or objects inside each other)") from None


class _KeyTwice(Exception):
    """A key given twice in one JSON object."""


def _once_each(pairs: list[tuple[str, Any]]) -> dict[str, Any]:
    """A JSON object whose keys are each given once: Python's parser keeps the last of a key given
    twice without a word (``"stationary"`` twice in meta.json took the second window)."""
    out: dict[str, Any] = {}
    for key, value in pairs:
        if key in out:
            raise _KeyTwice(key)
        out[key] = value
    return out
