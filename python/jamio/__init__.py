"""jamio: readers for the files jam writes (reference/schema.md).

    load_run(path)            one run file -> Run (attrs, data, units)
    load_runs(campaign_dir)   every run of a campaign -> one table of the run files' values
                              (pandas DataFrame if pandas is installed, else numpy arrays)
    load_stats(dir_or_file)   stats.h5 -> Stats (attrs, paper, ensembles, fit, fit_z)
    load_checks(dir_or_file)  checks.json (schema 1 or 2) and checks.h5 -> Checks

Tables on the campaign's nominal coordinates (n, phi_init, log10_rate, sample, and phi on the
output grid as exact values), with units; they need pandas, the Datasets xarray:

    runs_frame(campaign_dir), runs_dataset(campaign_dir)      every output point of every run
    stats_frame(stats), stats_dataset(stats)                  every ensemble's averages

An external campaign (runs jam did not plan, `jam campaign import DIR FILES...`: external.toml
instead of campaign.toml) reads with the same calls: its runs are those external.toml lists,
read as open runs (validate_run) on the nominal values external.toml gives each ensemble, with
the columns simulator and simulator_version; load_design(dir).external is its ExternalCampaign.

Writing a run of another simulator in the open run format (docs/cross-simulator.md):

    write_run(path, packing_fraction, pressure, *, dim, n, rate, phi_init, simulator, sample)
    validate_run(path)        an open run or a run file of jam's own, checked -> OpenRun
    write_frames(path, ...)   configurations for `jam import frames` (jam measures p, Z, E)
    python3 -m jamio.gsd_import   a HOOMD-blue GSD trajectory -> an open run (needs gsd)

Strings come back as str, numbers as int and float, datasets as numpy arrays. A file that is
missing or cannot be read raises JamioError (a ValueError) whose message starts with its path.
"""

from .campaign import (Design, ExternalCampaign, ExternalRun, is_external, load_design,
                       load_external)
from .checks import Checks, load_checks
from .errors import JamioError
from .frames import runs_dataset, runs_frame, stats_dataset, stats_frame
from .grid import grid_value
from .hdf5 import Group
from .runs import Run, load_external_runs, load_run, load_runs, run_files
from .stats import Ensemble, EnsembleKey, FamilyFit, Fit, Stats, load_stats
from .units import unit_of
from .open_run import OpenRun, validate_run
from .write import write_frames, write_run

__version__ = "0.2.0"

__all__ = ["Checks", "Design", "Ensemble", "EnsembleKey", "ExternalCampaign", "ExternalRun",
           "FamilyFit", "Fit", "Group", "JamioError", "OpenRun", "Run", "Stats", "grid_value",
           "is_external", "load_checks", "load_design", "load_external", "load_external_runs",
           "load_run", "load_runs", "load_stats", "run_files", "runs_dataset", "runs_frame",
           "stats_dataset", "stats_frame", "unit_of", "validate_run", "write_frames",
           "write_run", "__version__"]
