// Fingerprints identify stored runs, checkpoints, relaxed starts and campaign directories, so
// their text must never change for an existing configuration. The expected strings are fixed
// literals (taken from the version before the parameter table), not computed.
#include <boost/test/unit_test.hpp>
#include <string>

#include "sim/run/sim_config.hpp"

using jam::SimConfig;

namespace {

// Common tails of the expected strings.
const std::string kDefaultRelax =
    "skin=0.29999999999999999 diameter_ratio=1.3999999999999999 relax=true "
    "relax_energy=9.9999999999999998e-13 relax_time_max=10000 rattlers=false stress=false";

/// The defaults of the versions these literals come from: Heun was the overdamped default
/// until the Chebyshev integrator became it (a new configuration, with a new identity: below).
SimConfig heun_defaults() {
  SimConfig c;
  c.integrator = "heun";
  return c;
}

}  // namespace

BOOST_AUTO_TEST_CASE(defaults) {
  const SimConfig c = heun_defaults();
  BOOST_TEST(jam::fingerprint(c) ==
             "dim=2 n=1024 phi_init=0.59999999999999998 phi_stop=0.85999999999999999 "
             "phi_step=0.001 rate=0.0001 dt=0.10000000000000001 dynamics=overdamped "
             "integrator=heun q=0 seed=1 " +
                 kDefaultRelax + " read= jamming_point=false from=0");
  BOOST_TEST(jam::relaxation_fingerprint(c) ==
             "relaxation dim=2 n=1024 phi_init=0.59999999999999998 seed=1 "
             "dt=0.10000000000000001 dynamics=overdamped integrator=heun q=0 "
             "skin=0.29999999999999999 diameter_ratio=1.3999999999999999 "
             "relax_energy=9.9999999999999998e-13 relax_time_max=10000 read=");
}

BOOST_AUTO_TEST_CASE(read_from_lammps_data) {
  // n and phi_init come from the file: the fingerprints store 0 for them.
  SimConfig c = heun_defaults();
  c.read_lammps_data = "start.data";
  c.n = 512;
  c.phi_init = 0.7;
  c.dim = 3;
  BOOST_TEST(jam::fingerprint(c) ==
             "dim=3 n=0 phi_init=0 phi_stop=0.85999999999999999 phi_step=0.001 rate=0.0001 "
             "dt=0.10000000000000001 dynamics=overdamped integrator=heun q=0 seed=1 " +
                 kDefaultRelax + " read=start.data jamming_point=false from=0");
  BOOST_TEST(jam::relaxation_fingerprint(c) ==
             "relaxation dim=3 n=0 phi_init=0 seed=1 dt=0.10000000000000001 "
             "dynamics=overdamped integrator=heun q=0 skin=0.29999999999999999 "
             "diameter_ratio=1.3999999999999999 relax_energy=9.9999999999999998e-13 "
             "relax_time_max=10000 read=start.data");
}

BOOST_AUTO_TEST_CASE(inertial) {
  SimConfig c;
  c.dynamics = "inertial";
  c.quality_factor = 0.01;
  c.dt = 0.0001;
  c.seed = 9223372036854775807ULL;
  c.relax_energy = "1e-14";
  BOOST_TEST(jam::fingerprint(c) ==
             "dim=2 n=1024 phi_init=0.59999999999999998 phi_stop=0.85999999999999999 "
             "phi_step=0.001 rate=0.0001 dt=0.0001 dynamics=inertial integrator=verlet q=0.01 "
             "seed=9223372036854775807 skin=0.29999999999999999 "
             "diameter_ratio=1.3999999999999999 relax=true relax_energy=1e-14 "
             "relax_time_max=10000 rattlers=false stress=false read= jamming_point=false from=0");
  BOOST_TEST(jam::relaxation_fingerprint(c) ==
             "relaxation dim=2 n=1024 phi_init=0.59999999999999998 seed=9223372036854775807 "
             "dt=0.0001 dynamics=inertial integrator=verlet q=0.01 skin=0.29999999999999999 "
             "diameter_ratio=1.3999999999999999 relax_energy=1e-14 relax_time_max=10000 read=");
}

BOOST_AUTO_TEST_CASE(two_threads_and_every_switch) {
  SimConfig c = heun_defaults();
  c.threads = 2;
  c.integrator = "euler";
  c.compression_rate = 3.1622776601683794e-4;
  c.rattlers = c.stress = c.jamming_point = true;
  c.jamming_search_from = 0.8;
  c.relax = false;
  BOOST_TEST(jam::fingerprint(c) ==
             "dim=2 n=1024 phi_init=0.59999999999999998 phi_stop=0.85999999999999999 "
             "phi_step=0.001 rate=0.00031622776601683794 dt=0.10000000000000001 "
             "dynamics=overdamped integrator=euler q=0 seed=1 skin=0.29999999999999999 "
             "diameter_ratio=1.3999999999999999 relax=false "
             "relax_energy=1.0000000000000003e-11 relax_time_max=10000 rattlers=true "
             "stress=true read= jamming_point=true from=0.80000000000000004 threads=2");
  BOOST_TEST(jam::relaxation_fingerprint(c) ==
             "relaxation dim=2 n=1024 phi_init=0.59999999999999998 seed=1 "
             "dt=0.10000000000000001 dynamics=overdamped integrator=euler q=0 "
             "skin=0.29999999999999999 diameter_ratio=1.3999999999999999 "
             "relax_energy=1.0000000000000003e-11 relax_time_max=10000 read= threads=2");
}

BOOST_AUTO_TEST_CASE(three_dimensions) {
  SimConfig c = heun_defaults();
  c.dim = 3;
  c.n = 2048;
  c.phi_init = 0.45;
  c.phi_stop = 0.7;
  c.phi_step = 0.0005;
  c.skin = 0.25;
  c.diameter_ratio = 1.2;
  c.relax_time_max = 500;
  c.dt = 0.05;
  BOOST_TEST(jam::fingerprint(c) ==
             "dim=3 n=2048 phi_init=0.45000000000000001 phi_stop=0.69999999999999996 "
             "phi_step=0.00050000000000000001 rate=0.0001 dt=0.050000000000000003 "
             "dynamics=overdamped integrator=heun q=0 seed=1 skin=0.25 diameter_ratio=1.2 "
             "relax=true relax_energy=9.9999999999999998e-13 relax_time_max=500 "
             "rattlers=false stress=false read= jamming_point=false from=0");
  BOOST_TEST(jam::relaxation_fingerprint(c) ==
             "relaxation dim=3 n=2048 phi_init=0.45000000000000001 seed=1 "
             "dt=0.050000000000000003 dynamics=overdamped integrator=heun q=0 skin=0.25 "
             "diameter_ratio=1.2 relax_energy=9.9999999999999998e-13 relax_time_max=500 read=");
}

BOOST_AUTO_TEST_CASE(parameters_outside_the_physics_do_not_count) {
  // Output names, the wall-time checkpoint interval and the campaign a run belongs to never
  // change a run's numbers.
  SimConfig a, b;
  b.out = std::string("x.h5");
  b.checkpoint_interval = 5;
  b.quiet = b.force = true;
  b.campaign = std::string("campaign");
  b.sample = 3;
  b.write_lammps_data = std::string("w.data");
  BOOST_TEST(jam::fingerprint(a) == jam::fingerprint(b));
  BOOST_TEST(jam::relaxation_fingerprint(a) == jam::relaxation_fingerprint(b));
}

BOOST_AUTO_TEST_CASE(contact_law_is_a_suffix_only_when_not_harmonic) {
  SimConfig c = heun_defaults();
  c.contact = "harmonic";  // the default: fingerprints as before the parameter existed
  BOOST_TEST(jam::fingerprint(c) == jam::fingerprint(heun_defaults()));
  c.contact = "hertzian";
  BOOST_TEST(jam::fingerprint(c) ==
             "dim=2 n=1024 phi_init=0.59999999999999998 phi_stop=0.85999999999999999 "
             "phi_step=0.001 rate=0.0001 dt=0.10000000000000001 dynamics=overdamped "
             "integrator=heun q=0 seed=1 " +
                 kDefaultRelax + " read= jamming_point=false from=0 contact=hertzian");
  BOOST_TEST(jam::relaxation_fingerprint(c) ==
             "relaxation dim=2 n=1024 phi_init=0.59999999999999998 seed=1 "
             "dt=0.10000000000000001 dynamics=overdamped integrator=heun q=0 "
             "skin=0.29999999999999999 diameter_ratio=1.3999999999999999 "
             "relax_energy=9.9999999999999998e-13 relax_time_max=10000 read= contact=hertzian");
  c.threads = 2;  // both suffixes: threads first
  BOOST_TEST(jam::fingerprint(c) ==
             "dim=2 n=1024 phi_init=0.59999999999999998 phi_stop=0.85999999999999999 "
             "phi_step=0.001 rate=0.0001 dt=0.10000000000000001 dynamics=overdamped "
             "integrator=heun q=0 seed=1 " +
                 kDefaultRelax + " read= jamming_point=false from=0 threads=2 contact=hertzian");
  BOOST_TEST(jam::relaxation_fingerprint(c) ==
             "relaxation dim=2 n=1024 phi_init=0.59999999999999998 seed=1 "
             "dt=0.10000000000000001 dynamics=overdamped integrator=heun q=0 "
             "skin=0.29999999999999999 diameter_ratio=1.3999999999999999 "
             "relax_energy=9.9999999999999998e-13 relax_time_max=10000 read= threads=2 "
             "contact=hertzian");
}

// The Chebyshev integrator's default tolerance follows the rate (auto_tolerance); a run at
// 1e-4, the one tolerance before "auto", keeps the identity it had, and every other value is a
// suffix. The relaxation is at 1e-4 whatever the rate: one relaxed start serves every rate.
BOOST_AUTO_TEST_CASE(chebyshev_tolerance_is_a_suffix_only_when_not_1e_4) {
  SimConfig c;             // today's defaults: chebyshev, tolerance auto, rate 1e-4 -> 1e-2
  c.dense_output = false;  // as before dense output (its own case below)
  c.transient_tolerance = "off";
  c.stiffest_mode = "bound";
  BOOST_TEST(c.resolved_integrator() == "chebyshev");
  BOOST_TEST(jam::fingerprint(c) ==
             "dim=2 n=1024 phi_init=0.59999999999999998 phi_stop=0.85999999999999999 "
             "phi_step=0.001 rate=0.0001 dt=0.10000000000000001 dynamics=overdamped "
             "integrator=chebyshev q=0 seed=1 " +
                 kDefaultRelax + " read= jamming_point=false from=0 tolerance=0.01");
  const std::string relaxation =
      "relaxation dim=2 n=1024 phi_init=0.59999999999999998 seed=1 "
      "dt=0.10000000000000001 dynamics=overdamped integrator=chebyshev q=0 "
      "skin=0.29999999999999999 diameter_ratio=1.3999999999999999 "
      "relax_energy=1e-14 relax_time_max=10000 read=";
  c.relax_energy = "1e-14";  // as campaigns fix it, so that it does not follow the rate either
  BOOST_TEST(jam::relaxation_fingerprint(c) == relaxation);
  for (double rate : {1e-3, 1e-5, 1e-6, 1e-8}) {
    c.compression_rate = rate;
    BOOST_TEST(jam::relaxation_fingerprint(c) == relaxation);
  }
  // At 1e-6 and below auto is 1e-4: the fingerprint of the version before "auto".
  c.compression_rate = 1e-6;
  BOOST_TEST(jam::fingerprint(c).find("tolerance") == std::string::npos);
  c.compression_rate = 1e-5;
  BOOST_TEST(jam::fingerprint(c).ends_with(" tolerance=0.001"));
  // Given explicitly: the relaxation uses it too.
  c.tolerance = "1e-4";
  BOOST_TEST(jam::fingerprint(c).find("tolerance") == std::string::npos);
  c.tolerance = "1e-5";
  BOOST_TEST(jam::fingerprint(c).ends_with(" tolerance=1.0000000000000001e-05"));
  BOOST_TEST(jam::relaxation_fingerprint(c) == relaxation + " tolerance=1.0000000000000001e-05");
  // Integrators without error control ignore it: no suffix at auto.
  c.tolerance = "auto";
  c.integrator = "heun";
  c.compression_rate = 1e-3;
  BOOST_TEST(jam::fingerprint(c).find("tolerance") == std::string::npos);
}

BOOST_AUTO_TEST_CASE(auto_tolerance_is_100_rate_within_1e_4_and_3e_3) {
  // With dense output the fast rates' steps are no longer capped by the output grid: at most
  // 3e-3 (sim_config.hpp says what 1e-2 left).
  BOOST_TEST(jam::auto_tolerance(1e-3) == 3e-3);
  BOOST_TEST(jam::auto_tolerance(1e-4) == 3e-3);
  BOOST_TEST(jam::auto_tolerance(1e-5) == 1e-3, boost::test_tools::tolerance(1e-15));
  BOOST_TEST(jam::auto_tolerance(1e-3, false) == 1e-2);
  BOOST_TEST(jam::auto_tolerance(1e-4, false) == 1e-2);
  BOOST_TEST(jam::auto_tolerance(3e-6) == 3e-4, boost::test_tools::tolerance(1e-15));
  BOOST_TEST(jam::auto_tolerance(1e-6) == 1e-4, boost::test_tools::tolerance(1e-15));
  BOOST_TEST(jam::auto_tolerance(1e-9) == 1e-4);
  // The root-mean-square norm is at most the largest component: a tenth of it, as measured.
  BOOST_TEST(jam::auto_tolerance(1e-3, true, true) == 3e-4, boost::test_tools::tolerance(1e-15));
  BOOST_TEST(jam::auto_tolerance(1e-7, true, true) == 1e-5, boost::test_tools::tolerance(1e-15));
  SimConfig r;
  r.compression_rate = 1e-5;
  r.error_norm = "rms";
  BOOST_TEST(r.resolved_tolerance() == 1e-4, boost::test_tools::tolerance(1e-15));
  BOOST_TEST(r.relaxation_tolerance() == 1e-4);  // the relaxation keeps its norm and value
  r.compression_rate = 1e-7;
  BOOST_TEST(r.resolved_tolerance() == 1e-5, boost::test_tools::tolerance(1e-15));
  BOOST_TEST(r.resolved_transient_tolerance() == 0.0);  // the relaxation's is not tighter
  BOOST_TEST(jam::fingerprint(r).find(" tolerance=1.0000000000000001e-05 ") != std::string::npos);
  BOOST_TEST(jam::fingerprint(r).ends_with(" error_norm=rms"));
  r.integrator = "heun";  // no error control: neither applies
  BOOST_TEST(r.resolved_tolerance() == 1e-4);
  SimConfig c;
  c.tolerance = "tight";
  BOOST_CHECK_EXCEPTION(c.resolved_tolerance(), jam::ConfigError, [](const jam::ConfigError& e) {
    return std::string(e.what()) == "--tolerance tight: must be 'auto' or a number > 0";
  });
  c.tolerance = "0";
  BOOST_CHECK_THROW(c.resolved_tolerance(), jam::ConfigError);
}

// Dense output and the transient tolerance change the compression's numbers: a run at today's
// defaults says so in its fingerprint, a run with both off keeps the identity of the versions
// before them, and neither touches the relaxed start (one start serves both).
BOOST_AUTO_TEST_CASE(dense_output_and_transient_tolerance_are_suffixes) {
  SimConfig c;  // chebyshev at rate 1e-4: tolerance 3e-3, transient at the relaxation's 1e-4
  c.stiffest_mode = "bound";  // its own case below
  const std::string relaxation = jam::relaxation_fingerprint(c);
  BOOST_TEST(jam::fingerprint(c).ends_with(
      " tolerance=0.0030000000000000001 dense_output=true transient_tolerance=0.0001"));
  c.dense_output = false;  // landed steps: auto is 1e-2 at this rate, as before dense output
  BOOST_TEST(jam::fingerprint(c).ends_with(" tolerance=0.01 transient_tolerance=0.0001"));
  c.transient_tolerance = "3e-5";
  BOOST_TEST(jam::fingerprint(c).ends_with(" transient_tolerance=3.0000000000000001e-05"));
  c.transient_tolerance = "off";
  BOOST_TEST(jam::fingerprint(c).ends_with(" tolerance=0.01"));
  BOOST_TEST(jam::relaxation_fingerprint(c) == relaxation);
  // At 1e-6 the compression's tolerance is the relaxation's: no transient tolerance to apply.
  c = SimConfig{};
  c.compression_rate = 1e-6;
  c.stiffest_mode = "bound";
  BOOST_TEST(jam::fingerprint(c).find("transient_tolerance") == std::string::npos);
  BOOST_TEST(jam::fingerprint(c).ends_with(" dense_output=true"));
  // Integrators without error control have neither.
  c.integrator = "heun";
  c.compression_rate = 1e-3;
  BOOST_TEST(jam::fingerprint(c).find("dense_output") == std::string::npos);
  BOOST_TEST(jam::fingerprint(c).find("transient") == std::string::npos);
  // A malformed value: one line naming the option.
  c.integrator = "";
  c.transient_tolerance = "-1";
  try {
    c.resolved_transient_tolerance();
    BOOST_TEST(false, "accepted --transient-tolerance -1");
  } catch (const jam::ConfigError& e) {
    BOOST_TEST(std::string(e.what()).find("--transient-tolerance -1") != std::string::npos,
               e.what());
  }
}

// The stiffest-mode estimate changes the compression's numbers too: today's default says so
// last in the fingerprint, "bound" keeps the identity of the runs before it, the relaxed start
// is the same with either, and integrators without error control never carry it.
BOOST_AUTO_TEST_CASE(stiffest_mode_is_a_suffix) {
  SimConfig c;
  BOOST_TEST(jam::fingerprint(c).ends_with(" transient_tolerance=0.0001 stiffest_mode=estimate"));
  const std::string relaxation = jam::relaxation_fingerprint(c);
  const std::string estimate = jam::fingerprint(c);
  c.stiffest_mode = "bound";
  BOOST_TEST(jam::fingerprint(c) + " stiffest_mode=estimate" == estimate);
  BOOST_TEST(jam::relaxation_fingerprint(c) == relaxation);
  c.stiffest_mode = "estimate";
  c.integrator = "heun";
  BOOST_TEST(jam::fingerprint(c).find("stiffest_mode") == std::string::npos);
}

// So does the error norm: "rms" comes last; "max", the default, keeps the identity of the
// runs before it; the relaxed start is the same with either. (With tolerance "auto" the norm
// also sets the tolerance: auto_tolerance_is_100_rate_within_1e_4_and_3e_3.)
BOOST_AUTO_TEST_CASE(error_norm_is_a_suffix) {
  SimConfig c;
  c.tolerance = "3e-3";
  c.error_norm = "rms";
  BOOST_TEST(jam::fingerprint(c).ends_with(" stiffest_mode=estimate error_norm=rms"));
  const std::string relaxation = jam::relaxation_fingerprint(c);
  const std::string rms = jam::fingerprint(c);
  c.error_norm = "max";
  BOOST_TEST(jam::fingerprint(c) + " error_norm=rms" == rms);
  BOOST_TEST(jam::relaxation_fingerprint(c) == relaxation);
  c.integrator = "euler";
  c.error_norm = "rms";
  BOOST_TEST(jam::fingerprint(c).find("error_norm") == std::string::npos);
}
