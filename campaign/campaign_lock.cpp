#include "campaign/campaign_lock.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <string>

#include "campaign/campaign_file.hpp"

namespace jam {
namespace {

std::string owner_of(int fd) {
  char text[512] = "";
  const ssize_t got = ::pread(fd, text, sizeof text - 1, 0);
  std::string owner(text, got > 0 ? static_cast<std::size_t>(got) : 0);
  while (!owner.empty() && (owner.back() == '\n' || owner.back() == '\0')) owner.pop_back();
  return owner.empty() ? "another process" : owner;
}

}  // namespace

namespace {

/// Opens path and takes an flock of the given kind; throws CampaignError naming the holder, or
/// (wait) says who holds it and waits for it.
int lock_file(const std::string& path, const std::string& what, int kind, bool wait = false) {
  const int fd = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC | O_NOFOLLOW, 0644);
  if (fd < 0) {
    throw CampaignError(
        fmt::format("{}: cannot open the campaign's lock: {}", path, std::strerror(errno)));
  }
  if (::flock(fd, kind | LOCK_NB) != 0) {
    int error = errno;
    if (error == EWOULDBLOCK && wait) {
      fmt::print(stderr, "{}: in use by {}; waiting for it\n", what, owner_of(fd));
      // A signal ends the wait (EINTR) as an error: a waiting import stays interruptible.
      if (::flock(fd, kind) == 0) return fd;
      error = errno;
    }
    const std::string owner = owner_of(fd);
    ::close(fd);
    if (error == EWOULDBLOCK) {
      throw CampaignError(
          fmt::format("{}: in use by {} (another `jam campaign run` or import); wait for it to "
                      "finish or stop it",
                      what, owner));
    }
    throw CampaignError(fmt::format("{}: cannot lock: {}", path, std::strerror(error)));
  }
  return fd;
}

/// Notes "pid P on host H" in the lock file (only a second runner's message depends on it).
void note_owner(int fd) {
  char host[256] = "";
  ::gethostname(host, sizeof host - 1);
  const std::string owner = fmt::format("pid {} on host {}\n", ::getpid(), host);
  if (::ftruncate(fd, 0) == 0) {
    [[maybe_unused]] const auto written = ::pwrite(fd, owner.data(), owner.size(), 0);
  }
}

}  // namespace

CampaignLock::CampaignLock(const std::string& directory, const std::string& shard, bool wait) {
  const std::string path = directory + "/.lock";
  if (shard.empty()) {
    fd_ = lock_file(path, directory, LOCK_EX, wait);
    note_owner(fd_);
    return;
  }
  // Shares take the campaign's lock shared: an unsharded runner holding it refuses them.
  fd_ = lock_file(path, directory, LOCK_SH);
  try {
    shard_fd_ = lock_file(path + ".shard-" + shard, directory + " (share " + shard + ")", LOCK_EX);
  } catch (...) {
    ::close(fd_);
    throw;
  }
  note_owner(shard_fd_);
}

CampaignLock::~CampaignLock() {
  if (shard_fd_ >= 0) ::close(shard_fd_);  // releases the locks
  if (fd_ >= 0) ::close(fd_);
}

}  // namespace jam
