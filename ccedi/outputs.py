"""Result files written atomically (temporary file, then rename), so an interrupted run
never leaves a half-written output behind."""
import json
import math
import os
import tempfile
from pathlib import Path

from ccedi.errors import InputError


def atomic_write(path, write):
    """Call ``write(tmp)`` on a temporary file beside ``path``, then rename it over ``path``.

    An interrupted or failed write leaves neither a partial ``path`` nor the temporary
    file; an :class:`OSError` (a full disk, a quota, a file too large) is raised again
    naming ``path``, the file the user asked for, not the temporary one.

    Parameters
    ----------
    path : str or pathlib.Path
        Output file; parent directories are created.
    write : callable
        ``write(tmp)`` writes the whole content to the path ``tmp``.

    Returns
    -------
    pathlib.Path
        ``path``.

    Raises
    ------
    OSError
        The directory or the file cannot be written; ``filename`` is ``path``.
    """
    path = Path(path)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    except OSError as err:
        raise _naming(err, path) from None
    os.close(fd)
    umask = os.umask(0)
    os.umask(umask)
    os.chmod(tmp, 0o666 & ~umask)       # mkstemp makes 0600; give the file the usual permissions
    try:
        write(tmp)
        os.replace(tmp, path)
    except BaseException as err:
        if os.path.exists(tmp):
            os.unlink(tmp)
        if isinstance(err, OSError):
            raise _naming(err, path) from None
        raise
    return path


def _naming(err, path):
    """``err`` as an OSError whose filename is ``path`` (its errno and message kept)."""
    return OSError(err.errno, err.strerror or str(err), str(path))


def _json_safe(value):
    """``value`` with numpy scalars made plain and NaN/inf replaced by None (null), so the
    file is valid JSON that any reader accepts."""
    if isinstance(value, dict):
        return {k: _json_safe(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_json_safe(v) for v in value]
    if hasattr(value, "item") and getattr(value, "ndim", 1) == 0:
        value = value.item()
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


def write_json(path, data):
    """Write ``data`` as indented JSON, atomically.

    numpy scalars become plain numbers and non-finite numbers (NaN, inf) become null,
    so the file is strict JSON.

    Parameters
    ----------
    path : str or pathlib.Path
        Output file; parent directories are created. Written to a temporary file in the
        same directory, then renamed over ``path``.
    data : dict or list
        JSON-serialisable data (numpy scalars allowed).

    Returns
    -------
    pathlib.Path
        The path written.
    """
    def write(tmp):
        with open(tmp, "w") as fh:
            json.dump(_json_safe(data), fh, indent=2, sort_keys=False, allow_nan=False)
            fh.write("\n")
    return atomic_write(path, write)


def report_figures(figures, path):
    """Print ``figures`` one per line and write them as JSON to ``path``, atomically.

    The output of the speed benchmarks (``benchmarks/``) and the validation studies
    (``validation/``): each script writes its figures to a JSON file next to itself.

    Parameters
    ----------
    figures : dict
        Flat mapping of figure names to values (numpy scalars allowed; NaN and inf are
        written as null, as by :func:`write_json`).
    path : str or pathlib.Path
        Output JSON file.

    Returns
    -------
    pathlib.Path
        The path written.
    """
    for key, value in figures.items():
        print(f"{key:28s} {value}")
    written = write_json(path, figures)
    print(f"wrote {path}")
    return written

def write_csv(path, frame):
    """Write a pandas DataFrame as CSV (no index; column names carry the units), atomically.

    Parameters
    ----------
    path : str or pathlib.Path
        Output file; parent directories are created. Written to a temporary file in the
        same directory, then renamed over ``path``.
    frame : pandas.DataFrame
        The table.

    Returns
    -------
    pathlib.Path
        The path written.
    """
    return atomic_write(path, lambda tmp: frame.to_csv(tmp, index=False))


def write_figure(path, fig):
    """Save a matplotlib figure (120 dpi, tight bounding box), atomically.

    Parameters
    ----------
    path : str or pathlib.Path
        Output file; parent directories are created. Written to a temporary file in the
        same directory, then renamed over ``path``.
        The suffix chooses the format (default png).
    fig : matplotlib.figure.Figure
        The figure.

    Returns
    -------
    pathlib.Path
        The path written.
    """
    fmt = Path(path).suffix.lstrip(".") or "png"
    return atomic_write(path, lambda tmp: fig.savefig(tmp, format=fmt, dpi=120, bbox_inches="tight"))


def write_text(path, text):
    """Write a text file (e.g. a markdown report), atomically.

    Parameters
    ----------
    path : str or pathlib.Path
        Output file; parent directories are created. Written to a temporary file in the
        same directory, then renamed over ``path``.
    text : str
        The content.

    Returns
    -------
    pathlib.Path
        The path written.
    """
    def write(tmp):
        with open(tmp, "w") as fh:
            fh.write(text)
    return atomic_write(path, write)


def require_parquet():
    """Check that pandas' Parquet engine (pyarrow) is installed.

    Raises
    ------
    InputError
        A one-line message with the install command, if pyarrow cannot be imported.
    """
    try:
        import pyarrow  # noqa: F401
    except ImportError:
        raise InputError("Parquet output needs pyarrow: pip install pyarrow (or write CSV instead)") from None


def write_parquet(path, frame):
    """Write a pandas DataFrame as Parquet, atomically (needs ``pip install 'ccedi[parquet]'``).

    Parameters
    ----------
    path : str or pathlib.Path
        Output file; parent directories are created. Written to a temporary file in the
        same directory, then renamed over ``path``.
    frame : pandas.DataFrame
        The table.

    Returns
    -------
    pathlib.Path
        The path written.

    Raises
    ------
    InputError
        If pyarrow is not installed.
    """
    require_parquet()
    return atomic_write(path, lambda tmp: frame.to_parquet(tmp, index=False))


def write_table(path, frame):
    """Write a DataFrame as Parquet if ``path`` ends in ``.parquet``, else as CSV.

    Parameters
    ----------
    path : str or pathlib.Path
        Output file; parent directories are created. Written to a temporary file in the
        same directory, then renamed over ``path``.
    frame : pandas.DataFrame
        The table.

    Returns
    -------
    pathlib.Path
        The path written.

    Raises
    ------
    InputError
        For a ``.parquet`` path when pyarrow is not installed.
    """
    return (write_parquet if Path(path).suffix == ".parquet" else write_csv)(path, frame)


def write_pdf_figures(path, images):
    """Write a PDF with one A4 page per image, atomically.

    Parameters
    ----------
    path : str or pathlib.Path
        Output file; parent directories are created. Written to a temporary file in the
        same directory, then renamed over ``path``.
    images : iterable of (path, str)
        (PNG file, caption) pairs, one page each, in order.

    Returns
    -------
    pathlib.Path
        The path written.
    """
    import matplotlib  # matplotlib loads only when a figure is drawn
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt  # matplotlib loads only when a figure is drawn
    from matplotlib.backends.backend_pdf import PdfPages  # matplotlib loads only when a figure is drawn

    def write(tmp):
        with PdfPages(tmp) as pdf:
            for src, caption in images:
                fig, ax = plt.subplots(figsize=(8.27, 11.69))
                ax.imshow(plt.imread(src))
                ax.set_axis_off()
                ax.set_title(caption, fontsize=9, wrap=True)
                pdf.savefig(fig)
                plt.close(fig)
    return atomic_write(path, write)


def remove_temporaries(directory):
    """Delete the temporary files an interrupted writer left under ``directory``.

    These are the ``.<name>.*.tmp`` files of a process killed before its own clean-up
    could run; the search is recursive.

    Parameters
    ----------
    directory : str or pathlib.Path
        Directory to clean.

    Returns
    -------
    int
        Number of files removed.
    """
    leftovers = [p for p in Path(directory).rglob(".*.tmp") if p.is_file()]
    for p in leftovers:
        p.unlink(missing_ok=True)
    return len(leftovers)
