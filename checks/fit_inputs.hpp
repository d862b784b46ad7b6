#pragma once
// The verdicts of a campaign directory that its scaling fit may use (stats/fit_verdicts.hpp),
// read through the one reader of verdict files (verdict_file.hpp): the caller of `jam stats`
// passes them in, so stats/ never reads checks.json.
#include <string>

#include "stats/fit_verdicts.hpp"

namespace jam::checks {

/// DIR/checks.json's phi_init and pooled constant-phi finite_size verdicts, and
/// DIR/checks-phi_init.json's phi_init verdicts; empty (files "") when neither file is there.
/// Throws, naming the file, field and value, when one is there but breaks the schema.
stats::FitVerdicts fit_verdicts(const std::string& directory);

}  // namespace jam::checks
