"""Reading the JSON files a user gives (a log folder's ``meta.json``, a calibration, a parameter
file): any content that is not JSON text is a ValueError naming the file and what is wrong."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

from ._paths import check_file


def read_json(path: Path) -> Any:
    """The JSON value of the file ``path``.

    A byte order mark before the text is left out.

    Raises:
        ValueError: naming ``path``: not a regular file (a named pipe would be waited on for
            ever), not UTF-8, not JSON (with the line and column), nested deeper than Python's
            JSON parser goes (it raises RecursionError there), or a key given twice in an object.
        OSError: the file cannot be read.
    """
    check_file(path)
    data = path.read_bytes()
    # Windows editors (Notepad) begin a UTF-8 file with a byte order mark, which RFC 8259 lets a
    # reader ignore; Python's parser refused it ("Unexpected UTF-8 BOM")
    text = data.removeprefix(_UTF8_BOM)
    try:
        return json.loads(text.decode("utf-8"), object_pairs_hook=_once_each)
    except _KeyTwice as e:
        raise ValueError(f"{path}: the key {e.args[0]!r} is given twice in one object; keep one") from None
    except json.JSONDecodeError as e:
        # "Expecting value" alone does not say the file is not JSON at all (a CSV given as --calibration)
        raise ValueError(f"{path}: not valid JSON: line {e.lineno} column {e.colno}: {e.msg}") from None
    except UnicodeDecodeError as e:
        at = e.start + len(data) - len(text)  # of the file, its byte order mark included
        raise ValueError(f"{path}: not UTF-8 text (at byte offset {at}: {e.reason}); save it as UTF-8") from None
    except RecursionError:
        raise ValueError(f"{path}: JSON nested too deeply to read (arrays or objects inside each other)") from None


def json_kind(value: Any) -> str:
    """What a JSON value is, in JSON's words, and how it begins (``an array: [1, 2]``): an error
    about a file that holds the wrong kind of value says what it holds."""
    if value is None:
        return "null"
    kind = next(name for types, name in _KINDS if isinstance(value, types))
    text = json.dumps(value)
    return f"{kind}: {text if len(text) <= _SHOWN else text[:_SHOWN].rstrip() + ' ...'}"


#: JSON's kinds of value as Python's parser gives them (bool before int: True is an int).
_KINDS: tuple[tuple[type | tuple[type, ...], str], ...] = (
    (bool, "a boolean"), ((int, float), "a number"), (str, "a string"), (list, "an array"), (dict, "an object"),
)
#: The characters of a value :func:`json_kind` shows (a file may hold a long array).
_SHOWN = 60
_UTF8_BOM = b"\xef\xbb\xbf"


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
