#pragma once
// What an output option may name, checked before any work. A file output (`--out run.h5`) must
// be a regular file or absent: a directory, FIFO, device node or socket there is refused, so
// that the final rename never swaps one of them for a regular file (as root, `--out /dev/full`
// would otherwise turn the device into an HDF5 file). A directory output (`--out-dir`, a
// campaign's `output`) must be a directory or absent.
//
// Symbolic links are written through: a link to a regular file (or to a directory, for a
// directory output) stands for its target, the result replaces the target, and the link stays
// as it was. A link that points nowhere, or at anything else, is refused.
//
// Inputs are checked too (check_input_file): only a regular file is ever opened for reading.
#include <stdexcept>
#include <string>

namespace jam {

/// An output path that names something jam must not replace (output_file_target).
struct OutputPathError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// The one route of every file output, options and files jam names itself (stats.h5,
/// checks.json, run files, checkpoints) alike: the path to write, `path` itself or the regular
/// file a symbolic link there points to. Throws OutputPathError "<path>: is a FIFO; ..." for a
/// FIFO, device, socket, directory or dangling link, before anything is written.
std::string output_file_target(const std::string& path);

/// The path to write for a file output: `path` itself, or the file a symbolic link there
/// points to. Throws ConfigError "--<option> <path>: ..." naming what is there otherwise.
std::string checked_output_file(const std::string& option, const std::string& path);

/// Checks a directory output (absent or a directory, links followed); throws ConfigError.
void check_output_directory(const std::string& option, const std::string& path);

/// Checks an input file before it is opened: absent (the caller says so in its own words) or a
/// regular file, links followed. A FIFO, device, socket or directory is refused with
/// std::runtime_error "<what> <path>: is a FIFO; only a regular file can be read", because
/// opening a FIFO waits for a writer that may never come. stat() itself never waits.
void check_input_file(const std::string& what, const std::string& path);

}  // namespace jam
