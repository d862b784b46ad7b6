// The stop request (sim/run/stop_signal.hpp), in forked children that install it as jam does:
// the first SIGTERM asks for a clean stop and the process goes on to write its checkpoint; a
// second one within a second is the same request (a batch system's signal to every process of
// a job step arriving with the one its script forwards); one more than a second later ends the
// process at once with 130; and a system call that waits returns EINTR instead of waiting on
// (sigaction without SA_RESTART). The end-to-end cases, with real runs and checkpoints, are in
// test_hostile_cli.cpp.
#include <sys/wait.h>
#include <unistd.h>

#include <boost/test/unit_test.hpp>
#include <cerrno>
#include <csignal>
#include <ctime>
#include <fstream>
#include <iterator>
#include <string>

#include "sim/run/stop_signal.hpp"

namespace {

// Child exit codes: each names the step that went wrong (130 is the handler's own).
constexpr int kNoStopRequested = 3, kSurvivedSecondSignal = 4, kNotInterrupted = 5;

void sleep_seconds(double s) {
  timespec t{static_cast<time_t>(s), static_cast<long>((s - static_cast<time_t>(s)) * 1e9)};
  while (::nanosleep(&t, &t) != 0 && errno == EINTR) {
  }
}

/// The state letter of /proc/PID/stat (R running, S sleeping, ...), '?' when unreadable.
char process_state(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto close = text.rfind(')');  // the command name may hold spaces and parentheses
  return close != std::string::npos && close + 2 < text.size() ? text[close + 2] : '?';
}

/// Runs `body` in a forked child (which must end with _exit) and returns its wait status. The
/// child is killed by SIGALRM if it blocks for more than 20 s, so a test cannot hang.
template <class Body>
int in_child(Body body) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::alarm(20);
    body();
    ::_exit(0);
  }
  int status = 0;
  ::waitpid(pid, &status, 0);
  return status;
}

}  // namespace

BOOST_AUTO_TEST_CASE(signals_within_a_second_are_one_request_a_later_one_ends_the_process) {
  int survived[2];
  BOOST_REQUIRE(::pipe(survived) == 0);
  const int status = in_child([&survived] {
    jam::install_stop_handlers();
    ::raise(SIGTERM);
    if (!jam::stop_was_requested()) ::_exit(kNoStopRequested);
    ::raise(SIGTERM);  // at once: the same request, the process goes on to its checkpoint
    const char byte = 1;
    if (::write(survived[1], &byte, 1) != 1) ::_exit(kNoStopRequested);
    sleep_seconds(1.2);
    ::raise(SIGTERM);  // a second later: a user or a batch system that will not wait
    ::_exit(kSurvivedSecondSignal);
  });
  ::close(survived[1]);
  char byte = 0;
  BOOST_TEST(::read(survived[0], &byte, 1) == 1);  // the signal within a second did not end it
  ::close(survived[0]);
  BOOST_TEST(WIFEXITED(status));
  BOOST_TEST(WEXITSTATUS(status) == 130);  // the later one did, at once
}

BOOST_AUTO_TEST_CASE(a_system_call_that_waits_returns_eintr_on_a_stop_signal) {
  int never[2], ready[2];
  BOOST_REQUIRE(::pipe(never) == 0);
  BOOST_REQUIRE(::pipe(ready) == 0);
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::alarm(20);
    jam::install_stop_handlers();
    char byte = 1;
    if (::write(ready[1], &byte, 1) != 1) ::_exit(kNotInterrupted);
    // Nobody writes: without the signal this read waits until the alarm ends the child.
    const ssize_t got = ::read(never[0], &byte, 1);
    ::_exit(got < 0 && errno == EINTR && jam::stop_was_requested() ? 0 : kNotInterrupted);
  }
  char byte = 0;
  BOOST_REQUIRE(::read(ready[0], &byte, 1) == 1);  // the handlers are installed
  // Then the child's only step is the read: once it sleeps, it sleeps there.
  while (process_state(pid) != 'S') sleep_seconds(0.005);
  ::kill(pid, SIGTERM);
  int status = 0;
  ::waitpid(pid, &status, 0);
  for (int fd : {never[0], never[1], ready[0], ready[1]}) ::close(fd);
  BOOST_TEST(WIFEXITED(status), "ended by signal " << (WIFSIGNALED(status) ? WTERMSIG(status) : 0));
  BOOST_TEST(WEXITSTATUS(status) == 0);
}
