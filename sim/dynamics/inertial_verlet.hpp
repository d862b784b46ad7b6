#pragma once
// Inertial dynamics with quality factor Q, m_i dv_i/dt = f_i^el - gamma_i (v_i - v_host(r_i)),
// integrated exactly as LAMMPS does with
//   fix nve + fix viscous (gamma per type) + fix deform 1 x/y/z trate -rate remap x,
// so that a short run can be compared with LAMMPS to near round-off. v_i is the velocity
// relative to the host flow (LAMMPS's v when fix deform remaps x); per step:
//   1. nve initial_integrate:  v += (dt/2) f/m;  x += dt v          (box still L(t))
//   2. pair force at the current, not yet deformed, box L(t)
//   3. viscous post_force:     f -= gamma v   (with the half-step v)
//   4. nve final_integrate:    v += (dt/2) f/m
//   5. deform end_of_step:     L -> L(t + dt), scaled positions unchanged (remap x)
// Stable for dt below about 2 m_s / gamma_s = 2 Q^2 (k_d V_s) in these units.
#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include "sim/dynamics/stepper_state.hpp"
#include "sim/dynamics/system.hpp"

namespace jam {

template <int D>
class InertialVerlet {
 public:
  static constexpr const char* kName = "verlet";
  static constexpr int kOrder = 2;

  InertialVerlet(std::size_t n, const StepperOptions& o) : InertialVerlet(n, o.quality_factor) {}
  InertialVerlet(std::size_t n, double quality_factor) : quality_factor_(quality_factor) {
    for (int d = 0; d < D; ++d) {
      velocity_[d].assign(n, 0.0);
      total_force_[d].assign(n, 0.0);
    }
  }

  /// Forces must be recomputed before the next step (LAMMPS's setup() at the start of a run).
  void reset() { have_forces_ = false; }

  const std::array<std::vector<double>, D>& velocity() const { return velocity_; }

  StepperState save_state() const {
    StepperState state;
    for (int d = 0; d < D; ++d) {
      state.emplace_back("velocity_" + std::to_string(d), velocity_[d]);
      state.emplace_back("total_force_" + std::to_string(d), total_force_[d]);
    }
    state.emplace_back("have_forces", std::vector<double>{have_forces_ ? 1.0 : 0.0});
    return state;
  }

  void load_state(const StepperState& state) {
    for (const auto& [name, values] : state) {
      for (int d = 0; d < D; ++d) {
        if (name == "velocity_" + std::to_string(d)) velocity_[d] = values;
        if (name == "total_force_" + std::to_string(d)) total_force_[d] = values;
      }
      if (name == "have_forces") have_forces_ = !values.empty() && values[0] != 0.0;
    }
  }

  template <class Contact>

  void step(System<D, Contact>& sys, double t, double dt) {
    const std::size_t n = sys.size();
    const auto* type = sys.particles.type.data();
    const auto mass = sys.species.masses(quality_factor_);
    const double box_length = sys.box.length(t);
    if (!have_forces_) {
      total_forces(sys, box_length);
      have_forces_ = true;
    }
    const std::array<double, 2> half_dt_over_m = {0.5 * dt / mass[0], 0.5 * dt / mass[1]};
    const double dt_over_length = dt / box_length;
    for (int d = 0; d < D; ++d) {
      double* v = velocity_[d].data();
      double* s = sys.particles.s[d].data();
      const double* f = total_force_[d].data();
      for (std::size_t i = 0; i < n; ++i) {
        v[i] += half_dt_over_m[type[i]] * f[i];
        s[i] = wrap_unit(s[i] + dt_over_length * v[i]);
      }
    }
    total_forces(sys, box_length);
    for (int d = 0; d < D; ++d) {
      double* v = velocity_[d].data();
      const double* f = total_force_[d].data();
      for (std::size_t i = 0; i < n; ++i) v[i] += half_dt_over_m[type[i]] * f[i];
    }
  }

 private:
  template <class Contact>
  void total_forces(System<D, Contact>& sys, double box_length) {
    sys.compute_elastic_forces(box_length);
    const std::size_t n = sys.size();
    const auto* type = sys.particles.type.data();
    for (int d = 0; d < D; ++d) {
      const double* v = velocity_[d].data();
      const double* fel = sys.force[d].data();
      double* f = total_force_[d].data();
      for (std::size_t i = 0; i < n; ++i) f[i] = fel[i] - sys.species.drag[type[i]] * v[i];
    }
  }

  double quality_factor_;
  bool have_forces_ = false;
  std::array<std::vector<double>, D> velocity_;
  std::array<std::vector<double>, D> total_force_;
};

}  // namespace jam
