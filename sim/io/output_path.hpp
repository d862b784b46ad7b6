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
#include <string>

namespace jam {

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
