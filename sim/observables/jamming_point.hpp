#pragma once
// The jamming point phi_Ji of one compression run (checks/ phi_init independence):
//
//   the lowest packing at which the configuration, energy-minimized with FIRE at fixed box to
//   a largest force below 1e-10, keeps a pressure above 1e-8,
//
// found by bisection over the configurations saved at the output points of the run, then
// refined between the last unjammed and the first jammed output point by bisection along the
// straight path between those two configurations (scaled positions interpolated with the
// minimum image, packing interpolated linearly), until the bracket is narrower than 1e-5.
// Between output points (1e-3 apart in phi) particles move little, so that path stands in for
// the trajectory the run did not store.
// Below jamming the minimized pressure is exactly 0 (no overlap left); above it p grows about
// linearly with phi - phi_Ji (p ~ 1e-5 at 1e-4 above), so 1e-8 separates the two cleanly.
// As the bisection narrows its bracket, the configurations outside it are released: they are
// never needed again, and the run's checkpoints shrink with them (at N = 32768 in 2D all of
// them take 505 MB, after four bisection decisions a sixteenth of that).
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "sim/dynamics/fire_minimizer.hpp"
#include "sim/observables/observables.hpp"

namespace jam {

inline constexpr double kJammedPressure = 1e-8;
inline constexpr double kJammingResolution = 1e-5;

struct SavedConfiguration {
  double packing_fraction = 0.0;
  std::vector<double> s;  // D x N scaled positions, dimension-major; empty once released
};

/// Releases the positions of the configurations outside saved[lo ... hi].
inline void release_outside(std::vector<SavedConfiguration>& saved, std::size_t lo,
                            std::size_t hi) {
  for (std::size_t k = 0; k < saved.size(); ++k) {
    if (k < lo || k > hi) std::vector<double>().swap(saved[k].s);
  }
}

struct JammingPoint {
  double packing_fraction = std::numeric_limits<double>::quiet_NaN();
  int minimizations = 0;   // the search's decisions, replayed ones included
  int replayed = 0;        // of those, taken from the answers of an earlier, stopped search
  bool bracketed = false;  // false: not jammed by the last saved point, or jammed at the first
  bool stopped = false;    // abandoned on request (`stop`): packing_fraction means nothing
};

/// Thrown out of a minimization abandoned on request; caught by find_jamming_point.
struct JammingSearchStopped {};

template <int D, class Contact>
bool jammed_after_minimization(System<D, Contact>& sys, const std::vector<double>& s, double phi,
                               const std::atomic<bool>* stop = nullptr) {
  const std::size_t n = sys.size();
  if (s.size() != D * n) {
    // A configuration released before (or a checkpoint's that disagrees with its answers).
    throw std::runtime_error("jamming-point search: the configuration at phi " +
                             std::to_string(phi) + " is needed but was not kept");
  }
  for (int d = 0; d < D; ++d)
    std::copy(s.begin() + static_cast<long>(d * n), s.begin() + static_cast<long>((d + 1) * n),
              sys.particles.s[d].begin());
  sys.neighbors.invalidate();
  const double length = CompressingBox<D>::length_for_packing(sys.box.particle_volume, phi);
  FireOptions options;
  options.stop = stop;
  if (minimize_fire(sys, length, options).stopped) throw JammingSearchStopped{};
  CompressingBox<D> fixed = sys.box;
  sys.box.initial_length = length;
  sys.box.compression_rate = 0.0;
  const double p = measure(sys, 0.0, false).pressure;
  sys.box = fixed;
  return p > kJammedPressure;
}

/// The decisions of a search so far, in order (1: jammed after minimization, 0: not). The
/// search is deterministic, so a search that stopped (its answers checkpointed with the run)
/// resumes by replaying them and minimizes only from where it stopped: at N = 32768 a
/// minimization near jamming takes minutes, a search about an hour.
using JammingAnswers = std::vector<std::uint32_t>;

/// Called after each decision the search makes (not after a replayed one).
struct NoCallback {
  void operator()() const {}
};

/// Bisection over the saved configurations (in increasing packing), then refinement.
/// sys is used as scratch: its particles are overwritten. Throws JammingSearchStopped when
/// `stop` becomes true during a minimization. `answers` (optional): replayed where it reaches,
/// each new decision appended, then `after_decision()` (a run takes a checkpoint when due).
/// The configurations outside the bracket are released after each bisection decision
/// (release_outside), before after_decision(); a search replayed from the same answers needs
/// only those kept.
template <int D, class Contact, class AfterDecision = NoCallback>
JammingPoint find_jamming_point_or_stop(System<D, Contact>& sys,
                                        std::vector<SavedConfiguration>& saved,
                                        const std::atomic<bool>* stop,
                                        JammingAnswers* answers = nullptr,
                                        AfterDecision after_decision = {}) {
  JammingPoint r;
  if (saved.size() < 2) return r;
  bool fresh = false;  // the last decision was made here, not replayed
  auto jammed = [&](const std::vector<double>& s, double phi) {
    const auto k = static_cast<std::size_t>(r.minimizations++);
    fresh = !(answers && k < answers->size());
    if (!fresh) {
      ++r.replayed;
      return (*answers)[k] != 0;
    }
    const bool j = jammed_after_minimization(sys, s, phi, stop);
    if (answers) answers->push_back(j ? 1 : 0);
    return j;
  };
  // After the bracket has taken the decision in (and released what it left).
  auto decided = [&] {
    if (fresh) after_decision();
  };
  const bool jammed_last = jammed(saved.back().s, saved.back().packing_fraction);
  decided();
  if (!jammed_last) return r;
  const bool jammed_first = jammed(saved.front().s, saved.front().packing_fraction);
  decided();
  if (jammed_first) return r;
  std::size_t lo = 0, hi = saved.size() - 1;  // saved[lo] unjammed, saved[hi] jammed
  while (hi - lo > 1) {
    const std::size_t mid = (lo + hi) / 2;
    (jammed(saved[mid].s, saved[mid].packing_fraction) ? hi : lo) = mid;
    release_outside(saved, lo, hi);
    decided();
  }
  const double phi0 = saved[lo].packing_fraction, phi1 = saved[hi].packing_fraction;
  double lam_lo = 0.0, lam_hi = 1.0;
  std::vector<double> s(saved[lo].s.size());
  while ((lam_hi - lam_lo) * (phi1 - phi0) > kJammingResolution) {
    const double mid = 0.5 * (lam_lo + lam_hi);
    for (std::size_t k = 0; k < s.size(); ++k) {
      s[k] = wrap_unit(saved[lo].s[k] + mid * minimum_image(saved[hi].s[k] - saved[lo].s[k]));
    }
    (jammed(s, phi0 + mid * (phi1 - phi0)) ? lam_hi : lam_lo) = mid;
    decided();
  }
  r.packing_fraction = phi0 + 0.5 * (lam_lo + lam_hi) * (phi1 - phi0);
  r.bracketed = true;
  return r;
}

/// find_jamming_point_or_stop, with a stop reported in the result (stopped = true).
template <int D, class Contact, class AfterDecision = NoCallback>
JammingPoint find_jamming_point(System<D, Contact>& sys, std::vector<SavedConfiguration>& saved,
                                const std::atomic<bool>* stop = nullptr,
                                JammingAnswers* answers = nullptr,
                                AfterDecision after_decision = {}) {
  try {
    return find_jamming_point_or_stop(sys, saved, stop, answers, after_decision);
  } catch (const JammingSearchStopped&) {
    JammingPoint r;
    r.stopped = true;
    return r;
  }
}

}  // namespace jam
