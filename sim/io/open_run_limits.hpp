#pragma once
// The open run format's numeric limits, each with its reason: one table, here. jam's validators
// (open_run.cpp, frames_import.cpp, external_campaign.cpp) read it, and `jam schema open-run`
// writes it into reference/schema/open_run.toml, which jamio reads, so that both refuse the
// same files (tests/test_format_corpus.py feeds both one corpus).
#include <cstdint>

namespace jam {

struct OpenRunLimits {
  std::int64_t max_whole;   // n and sample at most this (2^53)
  std::int64_t max_points;  // output points per series
  double diameter_ratio_min, diameter_ratio_max;
  double max_contacts_per_particle;
  double jamming_above, jamming_below;  // phi_Ji in (above, below), or NaN
  double phi_init_slack;                // first packing >= phi_init (1 - slack)
  double rate_tolerance;                // phi(t) = phi_init exp(D rate t), relative
  std::int64_t max_frame_particles;     // a frames file's n (it holds M x N x D positions)
  std::int64_t max_frames;              // a frames file's M
};

inline constexpr OpenRunLimits kOpenRunLimits{
    .max_whole = std::int64_t{1} << 53,
    .max_points = std::int64_t{1} << 26,
    .diameter_ratio_min = 1.0,
    .diameter_ratio_max = 2.0,
    .max_contacts_per_particle = 64.0,
    .jamming_above = 0.0,
    .jamming_below = 1.0,
    .phi_init_slack = 1e-9,
    .rate_tolerance = 1e-6,
    .max_frame_particles = std::int64_t{1} << 24,
    .max_frames = std::int64_t{1} << 20,
};

/// Why each limit is what it is (the schema file states it beside the value).
struct OpenRunLimitReasons {
  static constexpr const char* max_whole =
      "2^53 for n and sample: every whole number up to it is exact as a double, and TOML readers "
      "(external.toml) hold no larger integer exactly; an open run holds no per-particle data, "
      "so n needs no tighter bound (a frames file has its own: max_frame_particles)";
  static constexpr const char* max_points =
      "2^26 output points per series, as jam's own run files: a flipped bit in a shape must not "
      "become a multi-GB allocation";
  static constexpr const char* diameter_ratio =
      "d_big / d_small of a bidisperse mixture: 1 is monodisperse; beyond 2 a small particle "
      "fits between two big ones and the model's neighbor cutoffs no longer hold";
  static constexpr const char* max_contacts_per_particle =
      "Z = 2 N_contacts / N is about 4 (2D) and 6 (3D) at jamming and grows slowly above; 64 is "
      "far beyond any packing below phi = 1, yet keeps the constant-Z grid bounded (a flipped "
      "exponent bit, 4 -> 5e154, is refused)";
  static constexpr const char* jamming_packing_fraction =
      "phi_Ji of the run, a packing fraction: in (0, 1), or NaN when the run did not jam";
  static constexpr const char* phi_init_slack =
      "the first output packing may lie this far (relative) below phi_init: round-off of the "
      "box length";
  static constexpr const char* rate_tolerance =
      "phi(t) = phi_init exp(D rate t) must hold to this, relative, where time is stored: a box "
      "that does not shrink at the stated rate is refused";
  static constexpr const char* max_frame_particles =
      "2^24 particles in a frames file (not an open run): it holds M x N x D positions, read "
      "whole, so N is bounded by memory, far above any run jam imports";
  static constexpr const char* max_frames =
      "2^20 frames in a frames file: with max_frame_particles, a flipped bit in a shape must not "
      "become an allocation beyond memory";
};

/// The table (kOpenRunLimits), for the callers that take it by reference.
inline const OpenRunLimits& open_run_limits() {
  return kOpenRunLimits;
}

}  // namespace jam
