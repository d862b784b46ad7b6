#pragma once
// A campaign compared with itself passes whatever it holds, so the compare check refuses DIR
// and REF that are one campaign, in any of the forms it can take:
//   - one directory (the same path, a link to it, `compare_with` naming the campaign itself);
//   - run files of the same content in both runs/ directories (an import of REF's own files):
//     jam's run files by the content checksum they carry, other files by their bytes;
//   - the same runs in both stats.h5 files (copies of one result whose runs are not kept): a
//     row of DIR's pressure table equal to one of REF's at every grid value both have.
#include "checks/stats_data.hpp"

namespace jam::checks {

/// Throws std::runtime_error, one line saying which form was found, when dir and ref are one
/// campaign as above; returns when they are two.
void refuse_same_campaign(const StatsData& dir, const StatsData& ref);

}  // namespace jam::checks
