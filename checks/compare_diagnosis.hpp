#pragma once
// Why two codes differ, where the compare check (checks/compare_check.hpp) can tell: what a
// user porting a code needs beside "where" (docs/porting.md).
//   - The models: each side's model as its campaign directory records it (external.toml of an
//     imported campaign, campaign.toml of a planned one: dimension, diameter ratio, contact
//     law, dynamics and Q). A difference is named in every verdict of the comparison, which
//     still judges both sides: an inertial run at small Q is meant to agree with the
//     overdamped model, one at Q = 2 is not, and the numbers say which.
//   - The start: a pressure verdict that fails, and no longer fails when judged again from
//     kStartSection in packing past where the compression takes over, fails only in the first
//     points after the start. That is where a start relaxed otherwise than jam's (CG
//     minimisation) differs first, so the reason points at the start protocol.
//   - Too few samples: a side with fewer than 2 samples is named with its count.
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "checks/pooled_verdict.hpp"
#include "checks/verdict.hpp"

namespace jam::checks {

/// The model of one side, as its campaign directory records it.
struct SideModel {
  int dim = 0;
  double diameter_ratio = 0;
  std::string contact, dynamics;
  double quality_factor = 0;  // inertial only
};

/// DIR's model from DIR/external.toml or DIR/campaign.toml; nullopt when it has neither (a
/// stats.h5 copied alone) or it does not read (the statistics name such files).
std::optional<SideModel> campaign_model(const std::string& directory);

/// How DIR's model differs from REF's, in words ("dynamics inertial (Q 2) against overdamped,
/// contact hertzian against harmonic"); "" when they are the same model.
std::string model_difference(const SideModel& dir, const SideModel& ref);

/// Appends the models' difference (model_difference) to the reason of every verdict of `out`
/// and sets its value model_differs = 1; nothing when either model is unknown or they agree.
void name_model_difference(std::vector<Verdict>& out, const std::optional<SideModel>& dir,
                           const std::optional<SideModel>& ref);

/// How far past where the compression takes over (in packing) the start still shows: the
/// start's transient the pointwise rule skips (margin.hpp, kStartTransient) and as much again.
constexpr double kStartSection = 0.01;

/// A failing pressure verdict v over `asked` whose judged range reaches below `past_start` (in
/// the range's variable: kStartSection past the compression's start) and lies mostly
/// (kNarrowShare, compare_coverage.hpp) beyond it: judged again over `asked` from `past_start`
/// (with `data`, the same grids). When that is judged and does not fail, v's reason says first
/// that it fails only just after the start and points at the start protocol; values
/// start_only = 1 and past_start = past_start. Otherwise v is unchanged.
void say_if_only_at_start(Verdict& v, const PoolRange& asked, double past_start,
                          const RangeData& data, Levels levels, double margin, int permutations);

/// "needs at least 2 samples per set (DIR has 1)" (both sides named when both have too few;
/// `what` qualifies the count, e.g. " with a jamming point"); "" when both have 2 or more.
std::string too_few_samples(std::size_t dir, std::size_t ref, const std::string& what = "");

}  // namespace jam::checks
