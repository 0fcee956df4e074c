"""Fuzzing the three input loaders: the study TOML (:func:`ccedi.study.config.load`), the
measured-record CSV (:func:`ccedi.rom.measurement.load_response`) and the JSON sidecar
(:func:`ccedi.calibrate.experiment.load_experiment`), directly and through ``ccedi``.

The property: any generated input either loads into an object that holds what the file
says, or is refused with one :class:`ccedi.errors.InputError` line (non-empty, printable,
no line break, a few hundred characters at most) that names the file or the field. Never
another exception, never a warning (they are errors here), never a hang: each case must
finish within ``DEADLINE`` (hypothesis fails a slower one) and is interrupted after
``HARD_LIMIT_S``. Through the command line a bad input is exit status 1 and one stderr
line, with the computation behind the loader replaced by a stub.

The inputs are valid examples (``ccedi init``'s TOML, bundled records and sidecars) with
mutations (keys dropped, renamed or added, values of another type or out of range, wrong
nesting, duplicated keys, cells and rows broken, columns dropped, renamed or repeated,
other delimiters and encodings, a BOM, garbage bytes, truncation), and random text and
bytes. Generation is derandomized, so every run tries the same cases.
"""
import contextlib
import copy
import io
import json
import math
import re
import signal
import tomllib
import warnings
from datetime import timedelta
from pathlib import Path
from unittest import mock

import numpy as np
import pytest
from conftest import ROOT
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

from ccedi.calibrate.experiment import DEFAULT_E_TOLERANCE, KINDS, load_experiment
from ccedi.errors import InputError
from ccedi.quantities import QUANTITIES
from ccedi.rom.measurement import MIN_SAMPLES, check_sampling, load_response
from ccedi.study.cli import main
from ccedi.study.config import SCHEMA, load, to_toml
from ccedi.study.config import example as init_toml
from ccedi.units import inch_to_m

DATA = ROOT / "data" / "measured"
RECORDS = ("control_low", "control_fea_solid")
EXAMPLES = 500                   # per input kind, in the normal run
LONG_EXAMPLES = 2500             # per input kind, in the slow run
CLI_EXAMPLES = 100               # per input kind, through the command line
DEADLINE = timedelta(seconds=5)  # per case; the loaders take milliseconds, 0.15 s for the largest file
HARD_LIMIT_S = 20.0
MAX_MESSAGE = 300                # characters, besides the file names

FUZZ = settings(max_examples=EXAMPLES, deadline=DEADLINE, derandomize=True, database=None,
                # a "huge" case builds a file of up to a megabyte from two drawn numbers: on a loaded
                # machine that can take longer than hypothesis allows for generating data
                suppress_health_check=[HealthCheck.too_slow])


@pytest.fixture(scope="module")
def workdir(tmp_path_factory):
    """One directory for the files of every case (each case overwrites the last), after
    the bundled examples have gone through the command line once (which also imports
    everything it needs before the first timed case)."""
    path = tmp_path_factory.mktemp("fuzz")
    (path / "example.toml").write_text(init_toml())
    assert _cli(["study", "--config", str(path / "example.toml"), "--out", str(path / "out")],
                "ccedi.study.run.run_study")
    for name in RECORDS:
        assert _cli(["calibrate", str(DATA / f"{name}.csv"), "--json", str(path / "out.json")],
                    "ccedi.calibrate.loop.calibrate")
    return path


# --- the property -----------------------------------------------------------------------

class Hang(Exception):
    """A case ran for more than HARD_LIMIT_S."""


@contextlib.contextmanager
def _bounded(seconds):
    """Interrupt the block after ``seconds`` of wall time (where the platform has SIGALRM)."""
    if not hasattr(signal, "setitimer"):
        yield
        return

    def alarm(signum, frame):
        raise Hang(f"the case ran for more than {seconds} s")

    previous = signal.signal(signal.SIGALRM, alarm)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)


def _assert_one_line(message, names):
    """The property of a refusal: one printable line, naming one of ``names``, short."""
    assert message and message.isprintable(), f"empty, or not one printable line: {message!r}"
    named = [name for name in names if name in message]
    assert named, f"names none of {names}: {message!r}"
    assert len(message) <= MAX_MESSAGE + sum(map(len, named)), f"{len(message)} characters: {message!r}"


def _attempt(load_it, *names):
    """``load_it()`` under the time limit with warnings as errors: its result, or None when
    it refuses with one InputError line naming one of ``names``. Any other exception
    propagates, and fails the test."""
    with _bounded(HARD_LIMIT_S), warnings.catch_warnings():
        warnings.simplefilter("error")
        try:
            return load_it()
        except InputError as err:
            _assert_one_line(str(err), names)
            return None


class Loaded(Exception):
    """Raised by the stub behind a loader on the command line: the input was accepted."""


def _stub(*args, **kwargs):
    raise Loaded


def _cli(argv, patch_target, *names):
    """Run ``ccedi ARGV`` with ``patch_target`` (the computation after loading) stubbed:
    True when the input loaded, False when ``ccedi`` refused it with exit status 1 and one
    stderr line naming one of ``names``."""
    err = io.StringIO()
    with (_bounded(HARD_LIMIT_S), mock.patch(patch_target, _stub), contextlib.redirect_stderr(err),
          contextlib.redirect_stdout(io.StringIO())):
        try:
            status = main(argv)
        except Loaded:
            return True
    text = err.getvalue()
    assert status == 1 and "Traceback" not in text, text
    lines = text.splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"ccedi {argv[0]}: error: "), text
    _assert_one_line(lines[0], names)
    return False


# --- values, mutations, serialisation ----------------------------------------------------

class Raw(str):
    """A token written into the file as it is (a 5000-digit number, deep nesting, ...)."""


RAW = [Raw(s) for s in ("9" * 5000, "-" + "9" * 400, "1e999", "-1e999", "NaN", "Infinity", "nan", "inf", "0x10",
                        "1_000", "01", "+1", ".5", "1979-05-27", "true", "null", "[" * 3000 + "]" * 3000,
                        "[" + "0.01, " * 3000 + "0.01]", "[" * 900 + "]" * 900,
                        "{" * 3000, "'quoted'", "\"unterminated")]
NASTY_TEXT = ["", " ", "6.1e6", "tip", "impulse", "contact", "nan", "1 in", "\ufeff", "é", "\n", "\t", "\x00",
              "\x1b[31m", "\u2028", "a" * 300, "[material]", "E_Pa = 1", "#", "\"", "'", "\\"]
CHARS = st.characters(blacklist_categories=("Cs",))


def _numbers(lo, hi):
    """Numbers in the range lo..hi and at and just beyond its ends."""
    edges = [lo, hi, math.nextafter(lo, -math.inf), math.nextafter(hi, math.inf), lo - 1.0, hi * 2.0 + 1.0, -hi, 0.0]
    return st.floats(lo, hi) | st.integers(math.floor(lo), math.ceil(hi)) | st.sampled_from(edges)


def _texts(*usual):
    """The strings ``usual``, and other strings."""
    return st.sampled_from(usual) | st.sampled_from(NASTY_TEXT) | st.text(CHARS, max_size=20)


def _values(dates=False):
    """Any value a TOML or JSON file can hold, and a few it cannot."""
    scalars = [st.none(), st.booleans(), st.integers(), st.sampled_from([0, -1, 1, 2**63 - 1, -2**63, 10**30, 10**400]),
               st.floats(), st.sampled_from([0.0, -0.0, math.nan, math.inf, -math.inf, 1e308, 5e-324, -1e-300]),
               st.text(CHARS, max_size=20), st.sampled_from(NASTY_TEXT), st.sampled_from(RAW)]
    if dates:
        scalars += [st.dates(), st.datetimes(), st.times()]
    keys = st.text(CHARS, max_size=8) | st.sampled_from(["E_Pa", "kind", "length_in", "time_s", ""])
    return st.recursive(st.one_of(scalars), lambda inner: st.lists(inner, max_size=4)
                        | st.dictionaries(keys, inner, max_size=3), max_leaves=8)


def _slots(data, path=""):
    """(container, key, dotted path) of every entry of a nested dict/list, containers first."""
    items = data.items() if isinstance(data, dict) else enumerate(data)
    for key, value in list(items):
        where = f"{path}.{key}" if path else str(key)
        yield data, key, where
        if isinstance(value, (dict, list)):
            yield from _slots(value, where)


def _renamed(key):
    """Near misses of a key: case, separators, a unit suffix, a stray character."""
    return [key.upper(), key + "_", key.replace("_", "-"), " " + key, key[:-1] or "x", key.split("_")[0],
            re.sub(r"_(in|m|s|Pa|N)$", "_mm", key), key + "\n", "é" + key]


def _set_field(draw, data, where, values):
    """Set the entry at the dotted path ``where`` (or one item of the list there) to one of
    ``values``, creating the tables on the way; nothing if a table on the way is something
    else."""
    *parents, leaf = where.split(".")
    for key in parents:
        data = data.setdefault(key, {})
        if not isinstance(data, dict):
            return
    value = draw(values)
    current = data.get(leaf)
    if isinstance(current, list) and current:
        current[draw(st.integers(0, len(current) - 1))] = value
    else:
        data[leaf] = value


@st.composite
def _mutated(draw, base, fields, extra_keys, dates=False):
    """``base`` with 0 to 4 mutations; ``fields`` maps the dotted path of an entry (list
    indices dropped) to a strategy of values for it, in and out of its range."""
    data = copy.deepcopy(base)
    values = _values(dates)
    for _ in range(draw(st.integers(0, 4))):
        slots = list(_slots(data))
        op = draw(st.sampled_from(["field"] * 4 + ["drop", "set", "raw", "scale", "edge", "add", "rename", "wrap",
                                                   "unwrap", "stringify", "resize"]))
        if op == "field":
            where = draw(st.sampled_from(sorted(fields)))
            _set_field(draw, data, where, fields[where])
            continue
        if not slots or op == "add":
            targets = [data] + [c[k] for c, k, _ in slots if isinstance(c[k], dict)]
            target = draw(st.sampled_from(targets))
            key = draw(st.sampled_from(extra_keys) | st.text(CHARS, max_size=10))
            target[key] = draw(values | st.sampled_from([copy.deepcopy(v) for v in base.values()]))
            continue
        container, key, where = draw(st.sampled_from(slots))
        value = container[key]
        if op == "drop":
            del container[key]
        elif op == "set":
            container[key] = draw(values)
        elif op == "raw":
            container[key] = draw(st.sampled_from(RAW))
        elif op == "scale" and isinstance(value, (int, float)) and not isinstance(value, bool) and abs(value) < 1e300:
            container[key] = value * draw(st.sampled_from([-1, 0, 1e-3, 0.999, 1.001, 1e3, 1e6, 1e300, -1e-300]))
        elif op == "edge":
            container[key] = draw(fields.get(re.sub(r"\.\d+(?=\.|$)", "", where), _numbers(0.0, 1.0)))
        elif op == "rename" and isinstance(container, dict):
            container[draw(st.sampled_from(_renamed(key)))] = container.pop(key)
        elif op == "wrap":
            container[key] = draw(st.sampled_from([[value], {"value": value}, [value, value]]))
        elif op == "unwrap" and isinstance(value, (list, dict)) and value:
            container[key] = next(iter(value.values() if isinstance(value, dict) else value))
        elif op == "stringify":
            container[key] = str(value)
        elif op == "resize" and isinstance(value, list):
            container[key] = value[:draw(st.integers(0, max(len(value) - 1, 0)))] or value * 3
    return data


@st.composite
def _text_mutated(draw, text):
    """``text`` as bytes, perhaps with a BOM, other line ends, a line repeated, dropped or
    added, a cut, garbage inserted, or in another encoding."""
    op = draw(st.sampled_from(["none"] * 6 + ["bom", "crlf", "cr", "repeat", "drop", "insert", "cut", "garbage",
                                               "utf16", "latin1"]))
    lines = text.splitlines(keepends=True)
    if op in ("repeat", "drop", "insert") and lines:
        i = draw(st.integers(0, len(lines) - 1))
        line = {"repeat": [lines[i], lines[i]], "drop": [],
                "insert": [draw(st.text(CHARS, max_size=30)) + "\n", lines[i]]}[op]
        text = "".join(lines[:i] + line + lines[i + 1:])
    elif op == "crlf":
        text = text.replace("\n", "\r\n")
    elif op == "cr":
        text = text.replace("\n", "\r")
    data = text.encode("utf-8", "surrogatepass")
    if op == "bom":
        data = b"\xef\xbb\xbf" + data
    elif op == "cut":
        data = data[:draw(st.integers(0, len(data)))]
    elif op == "garbage":
        i = draw(st.integers(0, len(data)))
        data = data[:i] + draw(st.binary(min_size=1, max_size=20)) + data[i:]
    elif op == "utf16":
        data = text.encode("utf-16", "surrogatepass")
    elif op == "latin1":
        data = text.encode("latin-1", "replace")
    return data


def _random_bytes():
    """Random bytes, and random text as UTF-8."""
    return st.binary(max_size=400) | st.text(CHARS, max_size=400).map(lambda s: s.encode())


# --- the study TOML -------------------------------------------------------------------------

TOML_FIELDS = {f"{s}.{k}": _numbers(spec.lo, spec.hi) if spec.lo is not None
               else st.booleans() if spec.kind is bool else _texts("serial", "local", "data/measured/control_low.csv")
               for s, keys in SCHEMA.items() for k, spec in keys.items()}
TOML_EXTRA = ["length_mm", "E_MPa", "impulse_length_mm", "solver", "notes", "alpha", "material", "study", "E_Pa"]
BASE_CONFIG = tomllib.loads(init_toml())
BARE_KEY = re.compile(r"[A-Za-z0-9_-]+")


def _toml_string(s):
    return json.dumps(s, ensure_ascii=False).replace("\x7f", "\\u007f")


def _toml_key(key):
    return key if BARE_KEY.fullmatch(key) else _toml_string(key)


def _toml_value(v):
    if isinstance(v, Raw):
        return str(v)
    if v is None:
        return "null"                                 # not TOML: a parse error
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, float):
        return "nan" if v != v else ("inf" if v == math.inf else "-inf" if v == -math.inf else repr(v))
    if isinstance(v, int):
        return str(v)
    if isinstance(v, str):
        return _toml_string(v)
    if isinstance(v, list):
        return "[" + ", ".join(map(_toml_value, v)) + "]"
    if isinstance(v, dict):
        return "{" + ", ".join(f"{_toml_key(str(k))} = {_toml_value(x)}" for k, x in v.items()) + "}"
    return v.isoformat()                              # date, datetime, time


def _toml_text(data):
    lines = [f"{_toml_key(k)} = {_toml_value(v)}" for k, v in data.items() if not isinstance(v, dict)]
    for section, entries in data.items():
        if isinstance(entries, dict):
            lines += [f"[{_toml_key(section)}]"] + [f"{_toml_key(k)} = {_toml_value(v)}" for k, v in entries.items()]
    return "\n".join(lines) + "\n"


@st.composite
def toml_files(draw):
    """Bytes of a study TOML: ``ccedi init``'s example mutated, or random text and bytes."""
    if draw(st.integers(0, 9)) == 0:
        return draw(_random_bytes() | st.text(st.sampled_from('[]{}=",.#\n _-+eE0123456789abtrufl\''), max_size=200)
                    .map(str.encode))
    return draw(_text_mutated(_toml_text(draw(_mutated(BASE_CONFIG, TOML_FIELDS, TOML_EXTRA, dates=True)))))


def _check_study_config(cfg, raw):
    """A loaded config holds what the file says, every default elsewhere, and writes back
    as a TOML file that loads to the same."""
    declared = tomllib.loads(raw.decode("utf-8-sig").replace("\r\n", "\n").replace("\r", "\n"))
    for section, keys in SCHEMA.items():
        for key, spec in keys.items():
            expected = declared.get(section, {}).get(key, spec.default)
            if key in ("measured_records", "design_calibration_record"):       # made absolute, one rule for paths
                expected = [Path(p).name for p in expected] if isinstance(expected, list) else Path(expected).name
                value = cfg[section][key]
                assert ([Path(p).name for p in value] if isinstance(value, list) else Path(value).name) == expected
                continue
            assert cfg[section][key] == expected, (section, key)


def _study_config_case(workdir, raw):
    path = workdir / "study.toml"
    path.write_bytes(raw)
    cfg = _attempt(lambda: load(path), str(path), *(f"[{s}]" for s in SCHEMA))
    if cfg is not None:
        _check_study_config(cfg, raw)
        path.write_text(to_toml(cfg), encoding="utf-8")
        assert load(path) == cfg


@FUZZ
@given(raw=toml_files())
@example(raw=b"[material]\nE_Pa = " + b"9" * 5000)                # int(): more than 4300 digits
@example(raw=b"[material]\nE_Pa = " + b"9" * 400)                 # float(): too large
@example(raw=b"x = " + b"[" * 3000 + b"]" * 3000)                  # tomllib: recursion
@example(raw=b'["\\u001f"]\nE_Pa = 1.0\n')                           # a control character in a name
@example(raw=b'[material]\n"\\u001f" = 1\n')
@example(raw=b"[material]\nE_Pa = [" + b"0.01, " * 3000 + b"0.01]\n")  # an 18 kB message
@example(raw=b'[study]\nscheduler = "\\n"\n')                       # written back as a raw line break
@example(raw=b"\xef\xbb\xbf[material]\nE_Pa = 6.1e6\n")                 # a BOM
def test_study_toml_loads_or_names_the_key(workdir, raw):
    _study_config_case(workdir, raw)


@pytest.mark.slow
@settings(FUZZ, max_examples=LONG_EXAMPLES)
@given(raw=toml_files())
def test_study_toml_loads_or_names_the_key_long(workdir, raw):
    _study_config_case(workdir, raw)


@settings(FUZZ, max_examples=CLI_EXAMPLES)
@given(raw=toml_files())
def test_study_command_refuses_a_bad_toml_in_one_line(workdir, raw):
    path = workdir / "cli.toml"
    path.write_bytes(raw)
    _cli(["study", "--config", str(path), "--out", str(workdir / "out")], "ccedi.study.run.run_study",
         str(path), *(f"[{s}]" for s in SCHEMA))
    assert not (workdir / "out").exists()


# --- the measured-record CSV --------------------------------------------------------------------

NUMBER = re.compile(r"\s*[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?\s*", re.ASCII)
COLUMNS = ("time_s", "tip_displacement_m", "force_N", "reaction_force_N")
CLEAN_CELLS = ["", "nan", "NaN", "inf", "-inf", "abc", "1e400", "-1e400", "0x10", "1_000", "True", "false", " 1.5 ",
               "١٢٣", "1e-3", "+2", ".5", "5.", "NULL", "None", "∞", "1.2.3", "9" * 400, "-0", "1e-320"]
DIRTY_CELLS = ["1,5", "\"", "\"a,b\"", "#", "1#2", "\x00", "a\nb", "'", ";", "\t"]
HEADER_NAMES = ["time_ms", "Time_s", "time_s ", "t", "tip_displacement_mm", "displacement", "force_N",
                "reaction_force_N", "note", "", "time_s", "tip_displacement_m", "time_s.1"]


@st.composite
def csv_tables(draw):
    """(header, rows) of a small record, each a list of cells, mutated; and whether every
    cell is free of delimiters, quotes and comment marks (a reference can read it)."""
    n = draw(st.sampled_from([0, 1, MIN_SAMPLES - 1, MIN_SAMPLES]) | st.integers(0, 40))
    dt = draw(st.sampled_from([1e-3] * 4 + [1e-4, 1.0, 1e-9, 1e-300]))
    t0 = draw(st.sampled_from([0.0] * 4 + [-1.0, 1e6, 1e300]))
    header = list(COLUMNS[:draw(st.integers(2, 4))])
    finite = st.floats(allow_nan=False, allow_infinity=False)
    rows = [[repr(t0 + i * dt)] + [repr(draw(finite)) for _ in header[1:]] for i in range(n)]
    clean = True
    for _ in range(draw(st.integers(0, 4))):
        op = draw(st.sampled_from(["cell", "dirty", "fill", "swap", "repeat", "ms", "reverse", "long_row", "short_row",
                                   "long_rows", "index", "drop_col", "rename", "dup_col", "add_col", "reorder"]))
        if op in ("cell", "dirty") and rows:
            row = draw(st.sampled_from(rows))
            row[draw(st.integers(0, len(row) - 1))] = draw(st.sampled_from(CLEAN_CELLS if op == "cell"
                                                                           else DIRTY_CELLS))
            clean &= op == "cell"
        elif op == "fill":
            j, cell = draw(st.integers(0, len(header) - 1)), draw(st.sampled_from(CLEAN_CELLS))
            rows = [r[:j] + [cell] + r[j + 1:] for r in rows]
        elif op == "swap" and len(rows) > 1:
            i, j = draw(st.integers(0, len(rows) - 1)), draw(st.integers(0, len(rows) - 1))
            rows[i][0], rows[j][0] = rows[j][0], rows[i][0]
        elif op == "repeat" and rows:
            i = draw(st.integers(0, len(rows) - 1))
            rows.insert(i, list(rows[i]))
        elif op == "ms":
            rows = [[repr(float(r[0]) * 1e3) if NUMBER.fullmatch(r[0]) else r[0]] + r[1:] for r in rows]
        elif op == "reverse":
            rows.reverse()
        elif op == "long_row" and rows:
            draw(st.sampled_from(rows)).append("0")
        elif op == "short_row" and rows:
            row = draw(st.sampled_from(rows))
            if len(row) > 1:
                row.pop()
        elif op == "long_rows":
            rows = [r + ["7"] for r in rows]
        elif op == "index":                           # a row number before every row, not in the header
            rows = [[str(i)] + r for i, r in enumerate(rows)]
        elif op == "drop_col" and len(header) > 1:
            j = draw(st.integers(0, len(header) - 1))
            header.pop(j)
            rows = [r[:j] + r[j + 1:] for r in rows]
        elif op == "rename":
            header[draw(st.integers(0, len(header) - 1))] = draw(st.sampled_from(HEADER_NAMES))
        elif op == "dup_col":
            header[draw(st.integers(0, len(header) - 1))] = draw(st.sampled_from(header))
        elif op == "add_col":
            header.append(draw(st.sampled_from(HEADER_NAMES)))
            rows = [r + [draw(st.sampled_from(["0", "x", "", "1e-3"]))] for r in rows]
        elif op == "reorder":
            order = draw(st.permutations(range(len(header))))
            header = [header[j] for j in order]
            rows = [[r[j] for j in order if j < len(r)] for r in rows]
    return header, rows, clean


@st.composite
def csv_files(draw):
    """(bytes of a record CSV, (header, rows) when a reference can read them, else None)."""
    source = draw(st.sampled_from(["table"] * 6 + ["bundled", "random", "huge"]))
    if source == "random":
        return draw(_random_bytes() | st.text(st.sampled_from("0123456789.,-+e\n#;\t abcnTime_s"), max_size=300)
                    .map(str.encode)), None
    if source == "bundled":
        name = draw(st.sampled_from(RECORDS))
        return draw(_text_mutated((DATA / f"{name}.csv").read_text())), None
    if source == "huge":                              # up to about a megabyte, from two drawn numbers
        n, seed = draw(st.integers(1000, 40000)), draw(st.integers(0, 2**32 - 1))
        y = np.random.default_rng(seed).standard_normal(n)
        text = "time_s,tip_displacement_m\n" + "".join(f"{i * 1e-3!r},{v!r}\n" for i, v in enumerate(y.tolist()))
        return draw(_text_mutated(text)), None
    header, rows, clean = draw(csv_tables())
    delimiter = draw(st.sampled_from([","] * 8 + [";", "\t", " ", "|"]))
    newline = draw(st.sampled_from(["\n", "\r\n", "\r"]))
    lines = [delimiter.join(header)] + [delimiter.join(r) for r in rows]
    if draw(st.booleans()):
        i = draw(st.integers(0, len(lines)))
        lines.insert(i, draw(st.sampled_from(["# recorded 2024-05-01, é", "", "#", "# time_s,x"])))
    text = newline.join(lines) + draw(st.sampled_from([newline, ""]))
    bom = draw(st.sampled_from([b"", b"", b"\xef\xbb\xbf"]))
    return bom + text.encode(), (header, rows) if clean and delimiter == "," else None


def _check_record(rec, table):
    """A loaded record is at least MIN_SAMPLES finite samples of strictly increasing time,
    and (where the table is known) the columns of the file under their names."""
    t = rec.time_s
    assert len(t) >= MIN_SAMPLES and np.all(t[1:] > t[:-1])
    for column in (rec.tip_displacement_m, rec.force_N, rec.reaction_force_N):
        assert column is None or (column.shape == t.shape and np.all(np.isfinite(column)))
    if table is None:
        return
    header, rows = table
    rows = [r for r in rows if r != [""]]             # an empty line is skipped
    assert all(len(r) <= len(header) for r in rows), "a row longer than the header was read"
    for name, column in zip(COLUMNS, (t, rec.tip_displacement_m, rec.force_N, rec.reaction_force_N)):
        assert (name in header) == (column is not None), name
        if column is not None:
            assert header.count(name) == 1, f"column {name} is repeated"
            j = header.index(name)
            cells = [r[j] if j < len(r) else "" for r in rows]
            assert all(NUMBER.fullmatch(c) for c in cells), f"column {name} read from {cells}"
            np.testing.assert_allclose(column, [float(c) for c in cells], rtol=1e-14, atol=0)


def _record_case(workdir, case):
    raw, table = case
    path = workdir / "record.csv"
    path.write_bytes(raw)
    rec = _attempt(lambda: load_response(path), str(path))
    if rec is not None:
        _check_record(rec, table)


def _csv(header, rows):
    """(bytes, table) of a clean record CSV."""
    return ("\n".join([",".join(header)] + [",".join(r) for r in rows]) + "\n").encode(), (header, rows)


RAMP = [[repr(i * 1e-3), repr(i * 1e-4)] for i in range(MIN_SAMPLES)]


@FUZZ
@given(case=csv_files())
@example(case=_csv(["time_s", "tip_displacement_m"], RAMP[:2] + [["1", "5", "0.0"]] + RAMP[3:]))   # two-line message
@example(case=_csv(["time_s", "tip_displacement_m", "time_s"], [r + ["0"] for r in RAMP]))        # a column twice
@example(case=_csv(["time_s", "tip_displacement_m"], [[str(i)] + r for i, r in enumerate(RAMP)]))  # one field more
@example(case=_csv(["time_s", "tip_displacement_m"], [[r[0], "True"] for r in RAMP]))             # read as 1.0
@example(case=_csv(["time_s", "tip_displacement_m"], [[repr((-1) ** i * 1.7e308), "0"] for i in range(9)]))  # overflow
def test_record_csv_loads_or_names_the_column(workdir, case):
    _record_case(workdir, case)


@pytest.mark.slow
@settings(FUZZ, max_examples=LONG_EXAMPLES)
@given(case=csv_files())
def test_record_csv_loads_or_names_the_column_long(workdir, case):
    _record_case(workdir, case)


@settings(FUZZ, max_examples=CLI_EXAMPLES)
@given(case=csv_files())
def test_calibrate_command_refuses_a_bad_record_in_one_line(workdir, case):
    csv, meta, out = workdir / "cli.csv", workdir / "cli.json", workdir / "cli_out.json"
    csv.write_bytes(case[0])
    meta.write_bytes((DATA / "control_low.json").read_bytes())
    _cli(["calibrate", str(csv), "--meta", str(meta), "--json", str(out)], "ccedi.calibrate.loop.calibrate",
         str(csv), str(meta))
    assert not out.exists()


# --- the JSON sidecar ----------------------------------------------------------------------------

SIDECAR_QUANTITIES = {"finger.length_in": "length_in", "finger.section_semi_axes_m": "section_semi_axis_m",
                      "finger.E_Pa": "E_Pa", "finger.nu": "nu", "finger.rho_kg_m3": "rho_kg_m3",
                      "load.force_N": "force_N", "load.duration_s": "pulse_duration_s", "load.start_s": "pulse_start_s",
                      "alpha_per_s": "alpha_per_s", "sensor.noise_std_m": "noise_std_m",
                      "tolerances.E_Pa": "E_tolerance"}
SIDECAR_FIELDS = {where: _numbers(QUANTITIES[q].lo, QUANTITIES[q].hi) for where, q in SIDECAR_QUANTITIES.items()} | {
    "finger.length_m": _numbers(inch_to_m(1.0), inch_to_m(12.0)), "kind": _texts(*KINDS), "load.at": _texts("tip")}
SIDECAR_EXTRA = ["length_m", "length_mm", "start_s", "alpha_per_s", "sensor", "tolerances", "noise_std_m", "notes",
                 "E_MPa", "at", "kind", "finger", "load"]


@st.composite
def sidecar_files(draw):
    """(record name, bytes of a sidecar): its bundled sidecar mutated, or random bytes."""
    name = draw(st.sampled_from(RECORDS))
    if draw(st.integers(0, 9)) == 0:
        return name, draw(_random_bytes() | st.text(st.sampled_from('{}[]:,"0123456789.eE-+ \n\tnultrufaseNI'),
                                                   max_size=200).map(str.encode))
    data = draw(_mutated(json.loads((DATA / f"{name}.json").read_text()), SIDECAR_FIELDS, SIDECAR_EXTRA))
    raws = {}

    def hide(v):                                      # a Raw token goes in as a marker string
        if isinstance(v, Raw):
            raws[f"@raw{len(raws)}@"] = v
            return f"@raw{len(raws) - 1}@"
        if isinstance(v, list):
            return [hide(x) for x in v]
        return {k: hide(x) for k, x in v.items()} if isinstance(v, dict) else v

    text = json.dumps(hide(data), ensure_ascii=draw(st.booleans()), indent=draw(st.sampled_from([None, 2])))
    for marker, token in raws.items():
        text = text.replace(json.dumps(marker), token)
    if draw(st.integers(0, 4)) == 0:                  # a key given twice: JSON keeps the second
        key, value = draw(st.sampled_from(SIDECAR_EXTRA)), draw(st.sampled_from([1, "impulse", None, [], {}]))
        text = text.replace("{", "{" + f"{json.dumps(key)}: {json.dumps(value)}, ", 1)
    return name, draw(_text_mutated(text))


def _check_experiment(exp, raw):
    """A loaded experiment holds what the sidecar says, every number within its range."""
    declared = json.loads(raw.decode("utf-8-sig"))
    finger, f = exp.finger, declared["finger"]
    assert exp.kind == declared["kind"] and exp.kind in KINDS
    length_m = inch_to_m(f["length_in"]) if "length_in" in f else f["length_m"]
    assert finger.length_m == pytest.approx(length_m, rel=1e-15)
    assert list(finger.semi_axes_m) == f["section_semi_axes_m"]
    assert (finger.E_Pa, finger.nu, finger.rho_kg_m3) == (f["E_Pa"], f["nu"], f["rho_kg_m3"])
    if exp.kind == "impulse":
        load_ = declared["load"]
        assert (exp.force_N, exp.duration_s) == (load_["force_N"], load_["duration_s"])
        assert exp.start_s == (load_.get("start_s") if load_.get("start_s") is not None else 0.0)
    assert exp.alpha_per_s == declared.get("alpha_per_s")
    assert exp.noise_std_m == declared.get("sensor", {}).get("noise_std_m")
    tol = declared.get("tolerances", {}).get("E_Pa")
    assert exp.E_tolerance == (DEFAULT_E_TOLERANCE if tol is None else tol)
    numbers = {"E_Pa": finger.E_Pa, "nu": finger.nu, "rho_kg_m3": finger.rho_kg_m3, "E_tolerance": exp.E_tolerance}
    for quantity, value in numbers.items():
        assert type(value) is float and QUANTITIES[quantity].lo <= value <= QUANTITIES[quantity].hi, quantity


def _sidecar_case(workdir, case):
    name, raw = case
    meta = workdir / "sidecar.json"
    meta.write_bytes(raw)
    csv = DATA / f"{name}.csv"
    exp = _attempt(lambda: load_experiment(csv, meta), str(meta), str(csv))
    if exp is not None:
        _check_experiment(exp, raw)


@FUZZ
@given(case=sidecar_files())
@example(case=(RECORDS[0], b"[" * 3000 + b"]" * 3000))                 # json: recursion
@example(case=(RECORDS[0], b'{"kind": ' + b"9" * 5000 + b"}"))         # int(): more than 4300 digits
@example(case=(RECORDS[0], b'{"kind": "' + b"9" * 5000 + b'"}'))       # a 5 kB message
@example(case=(RECORDS[0], b"\xef\xbb\xbf" + (DATA / f"{RECORDS[0]}.json").read_bytes()))  # a BOM
def test_sidecar_loads_or_names_the_field(workdir, case):
    _sidecar_case(workdir, case)


@pytest.mark.slow
@settings(FUZZ, max_examples=LONG_EXAMPLES)
@given(case=sidecar_files())
def test_sidecar_loads_or_names_the_field_long(workdir, case):
    _sidecar_case(workdir, case)


@settings(FUZZ, max_examples=CLI_EXAMPLES)
@given(case=sidecar_files())
def test_calibrate_command_refuses_a_bad_sidecar_in_one_line(workdir, case):
    name, raw = case
    meta, out = workdir / "cli_sidecar.json", workdir / "cli_sidecar_out.json"
    meta.write_bytes(raw)
    csv = DATA / f"{name}.csv"
    _cli(["calibrate", str(csv), "--meta", str(meta), "--json", str(out)], "ccedi.calibrate.loop.calibrate",
         str(meta), str(csv))
    assert not out.exists()


# --- the harness itself ---------------------------------------------------------------------------

def test_the_examples_load_and_the_property_can_fail(workdir):
    """The unmutated examples load (so the fuzzing starts from valid inputs), and the
    property's checks reject what they should."""
    _study_config_case(workdir, init_toml().encode())
    for name in RECORDS:
        _record_case(workdir, ((DATA / f"{name}.csv").read_bytes(), None))
        _sidecar_case(workdir, (name, (DATA / f"{name}.json").read_bytes()))
    with pytest.raises(AssertionError, match="names none"):
        _assert_one_line("something is wrong", ["study.toml"])
    with pytest.raises(AssertionError, match="printable"):
        _assert_one_line("study.toml: line one\nline two", ["study.toml"])
    with pytest.raises(AssertionError, match="longer than the header"):
        _check_record(load_response(DATA / "control_low.csv"),
                      (["time_s", "tip_displacement_m", "force_N"], [["0", "0", "0", "0"]]))
    with warnings.catch_warnings(), pytest.raises(InputError, match="steps up to inf s"):
        warnings.simplefilter("error")                # the step from -1e308 to 1e308 is beyond the float range
        check_sampling(np.array([-1e308, 1e308]), 100.0, "record.csv")
    with pytest.raises(Hang), _bounded(0.05):
        while True:
            pass
