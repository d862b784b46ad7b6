#pragma once
// Everything the dynamics acts on: particles, species constants, the contact law, the
// compressing box, the neighbor list and the elastic forces. The one force loop of the project
// lives here. The contact law is a template parameter (sim/model/contact_law.hpp); the paper's
// harmonic law is the default.
#include <array>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

#include "sim/dynamics/pair_forces.hpp"
#include "sim/model/compressing_box.hpp"
#include "sim/model/harmonic_contact.hpp"
#include "sim/model/particles.hpp"
#include "sim/model/species.hpp"
#include "sim/neighbor/neighbor_list.hpp"
#include "sim/parallel.hpp"

namespace jam {

template <int D, class Contact = HarmonicContact>
struct System {
  using ContactLaw = Contact;
  ParticleData<D> particles;
  Species<D> species;
  Contact contact;  // the pair law, its constants taken from the species
  CompressingBox<D> box;
  NeighborList<D> neighbors;
  std::array<std::vector<double>, D> force;  // elastic force f_i^el, physical units
  // The guard of update_neighbors against unstable fixed steps. Off for integrators that are
  // stable by construction (the Chebyshev one), whose long steps legitimately move particles
  // by more than the skin between force evaluations.
  bool guard_rebuilds = true;

 private:
  std::size_t evaluations_since_build_ = 0;
  std::uint64_t force_evaluations_ = 0;
  int consecutive_immediate_rebuilds_ = 0;

 public:
  System(ParticleData<D> p, const Species<D>& sp, const CompressingBox<D>& b, double skin)
      : particles(std::move(p)), species(sp), contact(sp), box(b), neighbors(skin) {
    for (auto& f : force) f.assign(particles.size(), 0.0);
  }

  std::size_t size() const { return particles.size(); }

  /// Bytes held by the particles, forces and neighbor list (capacities of their arrays).
  std::size_t memory_bytes() const {
    std::size_t b = neighbors.memory_bytes() + particles.type.capacity() +
                    particles.id.capacity() * sizeof(std::uint32_t);
    for (int d = 0; d < D; ++d) {
      b += (particles.s[d].capacity() + force[d].capacity()) * sizeof(double);
      for (const auto& partial : partial_force_) b += partial[d].capacity() * sizeof(double);
    }
    return b;
  }

  /// Makes the neighbor list valid for box length L.
  ///
  /// Guard against an unstable time step: explicit integration beyond its stability bound
  /// makes particles jump by more than the skin at every force evaluation, while positions stay
  /// wrapped and finite. A list that has to be rebuilt at every evaluation 50 times in a row is
  /// reported as an error instead of being allowed to produce quiet nonsense. (A stable run at
  /// any rate the project uses rebuilds every tens of steps; even the heavy overlaps of a random
  /// start move particles by ~0.1 per step at dt = 0.01, a rebuild every few steps.)
  void update_neighbors(double box_length) {
    ++evaluations_since_build_;
    if (neighbors.needs_rebuild(particles, box_length)) {
      consecutive_immediate_rebuilds_ =
          evaluations_since_build_ <= 1 ? consecutive_immediate_rebuilds_ + 1 : 0;
      if (guard_rebuilds && consecutive_immediate_rebuilds_ >= 50) {
        throw std::runtime_error(
            "the dynamics is unstable: particles cross the neighbor skin at every step (time step "
            "beyond the integrator's stability bound); reduce --dt");
      }
      neighbors.build(particles, species, box_length);
      evaluations_since_build_ = 0;
    }
  }

  /// Force evaluations so far (a measure of work that does not depend on the machine).
  std::uint64_t force_evaluations() const { return force_evaluations_; }

  /// Threads used by the force loop and the integrators' particle loops (1: serial).
  int threads() const { return threads_; }

  /// Sets the thread count (>= 1; at most available_threads()). Results are bitwise
  /// reproducible for a given count; see parallel.hpp.
  void set_threads(int threads) {
    if (threads < 1 || threads > available_threads()) {
      throw std::invalid_argument("threads must be between 1 and " +
                                  std::to_string(available_threads()));
    }
    threads_ = threads;
    neighbors.set_threads(threads);
    partial_force_.resize(static_cast<std::size_t>(threads - 1));
    for (auto& f : partial_force_)
      for (auto& c : f) c.assign(size(), 0.0);
    block_builds_ = 0;
  }

  /// f_i^el = sum_j f_ij^el at box length L (paper, "Model"). Half list, Newton's third law,
  /// branch-free pair evaluation, no allocation. With T > 1 threads, thread t takes the list
  /// rows of block t (blocks of equal pair count) into its own force array, and the arrays are
  /// summed in the order t = 0, 1, ..., T-1, so the sum does not depend on scheduling.
  void compute_elastic_forces(double box_length) {
    ++force_evaluations_;
    update_neighbors(box_length);
    if (threads_ == 1) {
      std::array<double*, D> f;
      for (int d = 0; d < D; ++d) f[d] = force[d].data();
      write_pair_forces(pair_loop_input(box_length), 0, size(), size(), f);
      return;
    }
#if defined(_OPENMP)
    if (block_builds_ != neighbors.builds()) split_rows_into_blocks();
    const std::size_t n = size();
#pragma omp parallel num_threads(threads_)
    {
      const int t = thread_number();
      const std::size_t first_row = block_start_[static_cast<std::size_t>(t)];
      // Thread t's pairs (i, j) have j > i >= first_row: it writes, and hands back, only
      // [first_row, n) of its own array.
      std::array<double*, D> f;
      for (int d = 0; d < D; ++d)
        f[d] = t == 0 ? force[d].data() : partial_force_[static_cast<std::size_t>(t - 1)][d].data();
      write_pair_forces(pair_loop_input(box_length), first_row,
                        block_start_[static_cast<std::size_t>(t) + 1], n, f);
#pragma omp barrier
      const std::size_t threads = partial_force_.size() + 1;
#pragma omp for schedule(static)
      for (std::size_t i = block_start_[1]; i < n; ++i) {
        for (std::size_t u = 1; u < threads && block_start_[u] <= i; ++u)
          for (int d = 0; d < D; ++d) force[d][i] += partial_force_[u - 1][d][i];
      }
    }
#endif
  }

  /// The pair loop's view of the system at box length L (pair_forces.hpp).
  PairLoopInput<D, Contact> pair_loop_input(double box_length) const {
    PairLoopInput<D, Contact> in{neighbors.offsets().data(),
                                 neighbors.neighbors().data(),
                                 neighbors.row_of_pair().data(),
                                 particles.type.data(),
                                 {},
                                 contact,
                                 box_length};
    for (int d = 0; d < D; ++d) in.s[d] = particles.s[d].data();
    return in;
  }

 private:
  /// Block t of rows starts where the list has t/T of its pairs (depends on the list only).
  void split_rows_into_blocks() {
    const auto& offsets = neighbors.offsets();
    const std::size_t n = size();
    const std::size_t threads = static_cast<std::size_t>(threads_);
    block_start_.assign(threads + 1, n);
    block_start_[0] = 0;
    std::size_t i = 0;
    for (std::size_t t = 1; t < threads; ++t) {
      const std::size_t target = offsets[n] * t / threads;
      while (i < n && offsets[i] < target) ++i;
      block_start_[t] = i;
    }
    block_builds_ = neighbors.builds();
  }

  int threads_ = 1;
  std::vector<std::array<std::vector<double>, D>> partial_force_;  // threads 1 .. T-1
  std::vector<std::size_t> block_start_;
  std::size_t block_builds_ = 0;
};

}  // namespace jam
