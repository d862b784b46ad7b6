"""jamio: readers for the files jam writes (reference/schema.md).

    load_run(path)            one run file -> Run (attrs, data, units)
    load_runs(campaign_dir)   every run of a campaign -> one table (pandas DataFrame if
                              pandas is installed, else a dict of numpy arrays)
    load_stats(dir_or_file)   stats.h5 -> Stats (attrs, paper, ensembles, fit, fit_z)
    load_checks(dir_or_file)  checks.json (schema 1 or 2) and checks.h5 -> Checks

Strings come back as str, numbers as int and float, datasets as numpy arrays. A file that is
missing or cannot be read raises JamioError (a ValueError) whose message starts with its path.
"""

from .checks import Checks, load_checks
from .errors import JamioError
from .hdf5 import Group
from .runs import Run, load_run, load_runs, run_files
from .stats import Ensemble, FamilyFit, Fit, Stats, load_stats

__version__ = "0.1.0"

__all__ = ["Checks", "Ensemble", "FamilyFit", "Fit", "Group", "JamioError", "Run", "Stats", "load_checks",
           "load_run", "load_runs", "load_stats", "run_files", "__version__"]
