"""A file's dialect: its encoding, delimiter, decimal mark, preamble and header line.

Detected from the file's first lines where that is unambiguous; the map's ``[file]`` sets
any of it (:class:`FileSettings`):

- the encoding: a byte-order mark says UTF-8 or UTF-16 (LE or BE); without one the file is
  UTF-16 if a quarter of its first bytes are NULs (LE if they are at odd offsets), UTF-8 if
  its first bytes are, else cp1251 (the Russian Windows code page);
- line ends: LF, CRLF or a CR alone (:mod:`rigclient.follow`);
- the header: the nearest line before the first data row (a line whose cells are all
  numbers) that has as many cells and no number among them; the lines before it are the
  preamble (a vendor's metadata, kept as the run's notes);
- the delimiter: the one of tab, semicolon, comma and runs of spaces that splits the header
  and the first data row into the same number (two or more) of cells, tried in that order;
- the decimal mark: a point, or a comma (``12,5``) in a cell that has no point; set to one
  of them, the other is refused. Quoted numbers (``"0.512"``) are numbers.

A number is ASCII digits with an optional sign, point and exponent: ``nan``, ``inf``, a
value beyond a double's range (``1e400``), digit group separators (``3_05``, ``1.234,5``)
and other scripts' digits (Arabic-Indic, full-width) are not numbers.
"""

from __future__ import annotations

import codecs
import csv
import math
import re
import unicodedata
from collections.abc import Iterable, Sequence
from dataclasses import dataclass

from rigclient.errors import InputError

#: The delimiters by their names in a map.
DELIMITERS = {"tab": "\t", "semicolon": ";", "comma": ",", "spaces": " ", "\t": "\t", ";": ";"}
DELIMITERS[","] = ","
DETECTED = ("\t", ";", ",", " ")
LOOK_BACK = 64  # lines before the first row in which its header is looked for
ENCODINGS = ("utf-8", "cp1251", "utf-16-le", "utf-16-be")
_BOMS = (
    (codecs.BOM_UTF8, "utf-8"),
    (codecs.BOM_UTF16_LE, "utf-16-le"),
    (codecs.BOM_UTF16_BE, "utf-16-be"),
)
_NUMBER = re.compile(r"[+-]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][+-]?[0-9]+)?")
_SPACES = re.compile(r"[ \t]+")
_WIDE_SPACES = re.compile(r" {2,}|\t")


@dataclass(frozen=True, slots=True)
class FileSettings:
    """What the map says of the file's dialect (None: detect it)."""

    encoding: str | None = None
    delimiter: str | None = None
    decimal: str | None = None
    header: int | None = None  # the header's line number (1-based)
    continue_time: bool = False  # a time that restarts goes on from where it ended


@dataclass(frozen=True, slots=True)
class Encoding:
    """A file's text encoding and the length of its byte-order mark."""

    codec: str
    bom: int = 0


def encoding_of(head: bytes, given: str | None = None) -> Encoding:
    """The encoding of a file that starts with ``head`` (the map's ``given`` wins; its BOM
    is skipped all the same)."""
    bom = next(((len(mark), codec) for mark, codec in _BOMS if head.startswith(mark)), None)
    if given is not None:
        codec = _codec(given)
        skip = bom[0] if bom is not None and bom[1] == codec else 0
        return Encoding(codec, skip)
    if bom is not None:
        return Encoding(bom[1], bom[0])
    if head.count(0) * 4 >= len(head) > 0:  # UTF-16 without a mark: NULs of ASCII letters
        odd = head[1::2].count(0)
        return Encoding("utf-16-le" if odd >= head[::2].count(0) else "utf-16-be")
    try:
        codecs.getincrementaldecoder("utf-8")().decode(head, final=False)
    except UnicodeDecodeError:
        return Encoding("cp1251")
    return Encoding("utf-8")


def _codec(name: str) -> str:
    try:
        codec = codecs.lookup(name).name
    except LookupError:
        raise InputError(f"unknown encoding {name!r}; known: {', '.join(ENCODINGS)}") from None
    codec = {"utf-8-sig": "utf-8", "utf-16": "utf-16-le", "windows-1251": "cp1251"}.get(
        codec, codec
    )
    if codec not in ENCODINGS:
        raise InputError(f"encoding {name!r} is not one of {', '.join(ENCODINGS)}")
    return codec


def delimiter_of(name: str) -> str:
    """A delimiter by its name in a map: ``tab``, ``semicolon`` (``;``), ``comma``
    (``,``), ``spaces``."""
    try:
        return DELIMITERS[name]
    except KeyError:
        raise InputError(
            f"unknown delimiter {name!r}; one of tab, semicolon, comma, spaces"
        ) from None


def cells(text: str, delimiter: str) -> list[str]:
    """The cells of a line, quotes removed; runs of spaces (``" "``) split on any run of
    blanks."""
    if delimiter == " ":
        return [c.strip('"') for c in _SPACES.split(text.strip())]
    try:
        return next(csv.reader([text], delimiter=delimiter), [])
    except csv.Error as exc:
        raise InputError(f"cannot split the line: {exc}") from None


def header_cells(text: str, delimiter: str, width: int | None = None) -> list[str]:
    """The cells of a header line: with runs of spaces as the delimiter, names may hold a
    single space (``Friction Force [N]``) when two or more spaces or a tab part the names and
    that gives the rows' ``width``."""
    if delimiter == " ":
        wide = [c.strip().strip('"') for c in _WIDE_SPACES.split(text.strip())]
        if width is None or len(wide) == width:
            return wide
    return cells(text, delimiter)


def number(cell: str, decimal: str | None = None) -> float:
    """A cell as a number (see the module's docstring); ``ValueError`` says why not."""
    text = cell.strip()
    if "," in text and decimal != ".":
        if "." in text:
            raise ValueError(f"{text!r} has both a decimal point and a comma")
        text = text.replace(",", ".")
    elif decimal == "," and "." in text:
        raise ValueError(f"{text!r} has a point where the file's decimal mark is a comma")
    if not text:
        raise ValueError("an empty cell")
    # float() also takes "nan", "inf", "3_05" and other scripts' digits: not ours
    if text.isascii() and "_" not in text:
        try:
            value = float(text)
        except ValueError:
            pass
        else:
            if math.isfinite(value):
                return value
            if _NUMBER.fullmatch(text):
                raise ValueError(f"{cell.strip()!r} is beyond the range of a number (±1.8e308)")
    raise ValueError(f"{cell.strip()!r} is not a number")


def is_number(cell: str, decimal: str | None = None) -> bool:
    try:
        number(cell, decimal)
    except ValueError:
        return False
    return True


def is_data(text: str, delimiter: str, decimal: str | None = None) -> bool:
    """Whether every cell of the line is a number (an empty last cell aside)."""
    found = cells(text, delimiter)
    if found and not found[-1].strip():
        found = found[:-1]
    return bool(found) and all(is_number(c, decimal) for c in found)


@dataclass(frozen=True, slots=True)
class Header:
    """The header found among a file's first lines: its index among them, and the
    delimiter."""

    index: int
    delimiter: str


_BRACKETED = re.compile(r"^(?P<name>.*?)\s*(?:\[(?P<a>[^\]]*)\]|\((?P<b>[^)]*)\))$")
_COMMA = re.compile(r"^(?P<name>[^,]*?)\s*,\s*(?P<unit>[^,]+)$")


def split_header(cell: str, delimiter: str) -> tuple[str, str | None]:
    """A header cell as (name, unit or None): ``load [kN]``, ``load (kN)``, ``load, kN``."""
    cell = cell.strip()
    found = _BRACKETED.match(cell)
    if found:
        return found["name"].strip(), (found["a"] or found["b"] or "").strip() or None
    found = _COMMA.match(cell) if delimiter != "," else None
    if found:
        return found["name"].strip(), found["unit"].strip()
    return cell, None


def name_key(text: str) -> str:
    """A column's name as it is looked up: NFKC (the micro sign is μ), case folded, blanks
    and dashes as one ``_`` (``Friction Force`` finds ``friction_force``)."""
    folded = unicodedata.normalize("NFKC", text).casefold().strip()
    return re.sub(r"[\s_-]+", "_", folded)


def header_names(found: Iterable[str], delimiter: str) -> frozenset[str]:
    """The names of a header's cells (:func:`name_key`), units left out, blanks skipped."""
    return frozenset(name_key(split_header(c, delimiter)[0]) for c in found if c.strip())


def find_header(
    lines: Sequence[str], settings: FileSettings, *, final: bool, first: int = 1
) -> Header | None:
    """The header among ``lines`` (the file's from its line ``first``), or None while no
    data row follows one (a file being written; ``final``: the file is whole, and then the
    last line of names, with no number among its cells, is the header)."""
    given = None if settings.delimiter is None else delimiter_of(settings.delimiter)
    if settings.header is not None:
        index = settings.header - first
        if index >= len(lines):
            return None
        if given is not None:
            return Header(index, given)
        following = next((t for t in lines[index + 1 :] if t.strip()), None)
        if following is None and not final:
            return None
        return Header(index, _split_alike(lines[index], following, settings.decimal))
    for k, text in enumerate(lines):
        if not text.strip():
            continue
        for delimiter in (given,) if given is not None else DETECTED:
            if not is_data(text, delimiter, settings.decimal):
                continue
            start = max(k - 1 - LOOK_BACK, -1)
            for j in range(k - 1, start, -1):  # past poison lines
                if lines[j].strip() and _row_of(lines[j], text, delimiter, settings.decimal):
                    return Header(_first_of(lines, j, start, delimiter), delimiter)
    if not final:
        return None
    for k in range(len(lines) - 1, -1, -1):  # no row: the last line of names is the header
        delimiter = given or _split_alike(lines[k], None, settings.decimal)
        names = [c for c in header_cells(lines[k], delimiter) if c.strip()]
        if names and not any(is_number(c) for c in names):
            return Header(k, delimiter)
    return None


def _first_of(lines: Sequence[str], j: int, start: int, delimiter: str) -> int:
    """The header ``lines[j]``, or the first line above it (after ``start``) with the same
    names, in any order and unit: a header repeated after rows that cannot be read, which
    are then rows of the file, not its preamble."""
    names = _names(lines[j], delimiter)
    if not names:
        return j
    return next((i for i in range(start + 1, j) if _names(lines[i], delimiter) == names), j)


def _names(text: str, delimiter: str) -> frozenset[str]:
    """The names of a header line (:func:`header_names`); none if it cannot be split."""
    try:
        return header_names(header_cells(text, delimiter), delimiter)
    except InputError:
        return frozenset()


def _row_of(header: str, row: str, delimiter: str, decimal: str | None) -> bool:
    """Whether ``row`` is a data row under ``header``, split by ``delimiter``: as many
    cells, two or more, and no number among the header's."""
    if not is_data(row, delimiter, decimal):
        return False
    width = len(cells(row, delimiter))
    names = header_cells(header, delimiter, width)
    if any(is_number(c) for c in names if c.strip()):
        return False
    return len(names) == width >= 2


def _split_alike(header: str, row: str | None, decimal: str | None) -> str:
    """The delimiter of a header (and the row after it, if any)."""
    if row is not None:
        for delimiter in DETECTED:
            if _row_of(header, row, delimiter, decimal):
                return delimiter
    return next((d for d in DETECTED[:-1] if d in header), " ")
