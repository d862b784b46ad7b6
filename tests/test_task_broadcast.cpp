// The tasks of a campaign as the one integer array rank 0 broadcasts to the others
// (campaign/run_chains.hpp): every task, its order and which runs are done only to their
// start come back as they were, for the edge cases of the encoding: run 0 start-only (the code
// nearest kEndOfTask), an empty plan, a task of one run, and the largest index of a plan.
#include <boost/test/unit_test.hpp>

#include "campaign/run_chains.hpp"

namespace {

jam::RunTasks tasks(std::vector<std::vector<std::size_t>> t, std::vector<bool> start_only) {
  jam::RunTasks r;
  r.tasks = std::move(t);
  r.start_only = std::move(start_only);
  return r;
}

void round_trip(const jam::RunTasks& t) {
  const auto codes = jam::tasks_for_broadcast(t);
  const jam::RunTasks back = jam::tasks_from_broadcast(codes, t.start_only.size());
  BOOST_TEST(back.tasks == t.tasks);
  BOOST_TEST(back.start_only == t.start_only);
}

}  // namespace

BOOST_AUTO_TEST_CASE(tasks_come_back_as_they_were) {
  round_trip(tasks({{0, 3}, {2}, {1}}, {true, false, false, false}));  // run 0 only to its start
  round_trip(tasks({{4, 1, 0}, {3, 2}}, {false, true, false, true, false}));
  round_trip(tasks({}, {}));
  round_trip(tasks({{7}}, std::vector<bool>(8, false)));
  round_trip(tasks({{7}}, {false, false, false, false, false, false, false, true}));
}

BOOST_AUTO_TEST_CASE(start_only_codes_lie_below_the_task_end) {
  // Run indices are >= 0 and kEndOfTask is -1: a start-only code must not meet either.
  BOOST_TEST(jam::start_only_code(0) < jam::kEndOfTask);
  BOOST_TEST(jam::start_only_code(5) == jam::kEndOfTask - 6);
  const auto codes = jam::tasks_for_broadcast(tasks({{1, 0}}, {true, false}));
  BOOST_TEST(codes == (std::vector<std::int64_t>{1, jam::start_only_code(0), jam::kEndOfTask}));
}
