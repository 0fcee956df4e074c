"""Command-line arguments shared by several sub-commands (nothing heavy is imported here)."""
from ccedi.fea.distributed import SERIAL


def add_scheduler_argument(parser, default=SERIAL):
    """Add ``--scheduler serial|local|ADDRESS`` to ``parser``.

    Parameters
    ----------
    parser : argparse.ArgumentParser
        The sub-command's parser.
    default : str or None
        Default scheduler; ``None`` leaves the choice to the command (e.g. a config file).
    """
    said = f"default {default}" if default is not None else "default: the config's scheduler"
    parser.add_argument("--scheduler", default=default, metavar="serial|local|ADDRESS",
                        help="where independent runs go: serial (this process), local (a 2-worker Dask local "
                             f"cluster) or a Dask scheduler address such as tcp://host:8786 ({said})")


def add_config_argument(parser):
    """Add ``--config TOML`` (the finger's material and section, the drum set-up) to ``parser``.

    Parameters
    ----------
    parser : argparse.ArgumentParser
        The sub-command's parser.
    """
    parser.add_argument("--config", help="inputs TOML ([material], [finger], [drum]; see ccedi init); "
                        "default: the paper's rubber finger and drum test")


def load_config(args):
    """The validated inputs of ``--config`` (all defaults when it is not given).

    Parameters
    ----------
    args : argparse.Namespace
        Parsed arguments, with an optional ``config`` path.

    Returns
    -------
    dict
        ``{section: {key: value}}`` as :func:`ccedi.study.config.load` returns it.

    Raises
    ------
    ccedi.errors.InputError
        The file is missing, not TOML, or holds a bad key or value.
    """
    from ccedi.study.config import load

    return load(getattr(args, "config", None))
