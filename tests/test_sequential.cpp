// Looking again after more samples (checks/sequential.hpp): the false-alarm rate of a whole
// sequence of looks, each adding samples to an undecided comparison as
// `jam campaign run --until-decided` does, measured on synthetic run sets with nothing
// planted: with alpha spent over the looks it stays at or below alpha; judging every look at
// the full alpha (what the spending prevents) exceeds it.
#include <boost/test/unit_test.hpp>
#include <cmath>
#include <random>

#include "checks/pooled_verdict.hpp"
#include "checks/sequential.hpp"
#include "synthetic_runs.hpp"

using namespace jam::checks;
using namespace jam::checks::testing;

namespace {

/// One sequence: 4 samples per set first, then next_samples() per look, up to 5 looks, a
/// verdict decided at a look is final. Returns the final status. `spend`: alpha per look as
/// look_alpha, else alpha at every look. Each look draws the added runs from the same
/// distribution (no effect), keeping the earlier ones, as added samples do.
std::string sequence(double alpha, bool spend, std::uint64_t seed, double margin) {
  std::mt19937_64 rng(seed);
  std::vector<std::vector<double>> a, b;
  long samples = 4;
  for (int look = 1; look <= 5; ++look) {
    const auto more_a = runs(static_cast<int>(samples - static_cast<long>(a.size())), 0.0, rng, 20);
    const auto more_b = runs(static_cast<int>(samples - static_cast<long>(b.size())), 0.0, rng, 20);
    a.insert(a.end(), more_a.begin(), more_a.end());
    b.insert(b.end(), more_b.begin(), more_b.end());
    Aligned al;
    for (std::size_t k = 0; k < 20; ++k) al.grid.push_back(0.80 + 0.001 * k);
    al.a = a;
    al.b = b;
    const double level = spend ? look_alpha(alpha, look) : alpha;
    Verdict v;
    judge_pooled(v, al, PoolRange{}, Levels{level, level}, margin, 100, seed);
    if (v.status != "inconclusive") return v.status;
    samples = next_samples(samples, v.samples_needed);
  }
  return "inconclusive";
}

}  // namespace

BOOST_AUTO_TEST_CASE(spending_sums_to_alpha) {
  double sum = 0;
  for (int k = 1; k <= 100000; ++k) sum += look_alpha(0.05, k);
  BOOST_TEST(sum == 0.05, boost::test_tools::tolerance(1e-4));  // the tail beyond 1e5 looks: 5e-7
  BOOST_TEST(look_alpha(0.05, 1) == 0.025);
  BOOST_CHECK_THROW(look_alpha(0.05, 0), std::invalid_argument);
  BOOST_TEST(next_samples(10, NAN) == 20);
  BOOST_TEST(next_samples(10, 12) == 15);
  BOOST_TEST(next_samples(10, 17.2) == 18);
  BOOST_TEST(next_samples(10, 400) == 20);
}

BOOST_AUTO_TEST_CASE(false_alarm_rate_of_whole_sequences) {
  // alpha 0.2 over the sequence keeps the permutation counts small (the rule is the same at
  // every level); a margin of 0.02 keeps most sequences undecided for several looks, which is
  // where repeated looks inflate false alarms. 300 sequences spent (the count), 100
  // naive (measured 0.58 over 300: far beyond alpha, so 100 show it).
  const int repeats = 300;
  const double alpha = 0.2;
  int spent_alarms = 0, naive_alarms = 0;
  for (int r = 0; r < repeats; ++r) {
    spent_alarms += sequence(alpha, true, 100 + static_cast<unsigned>(r), 0.02) == "fail";
    if (r < 100)
      naive_alarms += sequence(alpha, false, 100 + static_cast<unsigned>(r), 0.02) == "fail";
  }
  const double spent = double(spent_alarms) / repeats, naive = double(naive_alarms) / 100;
  BOOST_TEST_MESSAGE("false alarms over 5 looks at alpha 0.2: spent " << spent << ", naive "
                                                                      << naive);
  BOOST_TEST(spent <= alpha + 1.645 * std::sqrt(alpha * (1 - alpha) / repeats));
  BOOST_TEST(naive > alpha + 0.1);  // the looks do inflate it: the spending is needed
}
