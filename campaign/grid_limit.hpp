#pragma once
// The largest averaging grid the statistics build (stats/averages.cpp): a bound checked before
// anything is allocated, so that a step from a damaged run file or a typo cannot ask for
// gigabytes. The campaigns' grids have a few thousand points. `jam campaign import` refuses a
// --phi-step whose grid over packings in (0, 1) could exceed it (campaign/external_import.cpp),
// so that no import leaves a campaign the statistics then refuse. It lives here, below both, so
// that campaign/ includes nothing of the statistics above it.
namespace jam {

inline constexpr double kMaxGridPoints = 1e6;

}  // namespace jam
