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

CampaignLock::CampaignLock(const std::string& directory) {
  const std::string path = directory + "/.lock";
  fd_ = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC | O_NOFOLLOW, 0644);
  if (fd_ < 0) {
    throw CampaignError(
        fmt::format("{}: cannot open the campaign's lock: {}", path, std::strerror(errno)));
  }
  if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    const int error = errno;
    const std::string owner = owner_of(fd_);
    ::close(fd_);
    fd_ = -1;
    if (error == EWOULDBLOCK) {
      throw CampaignError(fmt::format(
          "{}: in use by {} (another `jam campaign run`); wait for it to finish or stop it",
          directory, owner));
    }
    throw CampaignError(fmt::format("{}: cannot lock: {}", path, std::strerror(error)));
  }
  char host[256] = "";
  ::gethostname(host, sizeof host - 1);
  const std::string owner = fmt::format("pid {} on host {}\n", ::getpid(), host);
  if (::ftruncate(fd_, 0) != 0 ||
      ::pwrite(fd_, owner.data(), owner.size(), 0) != static_cast<ssize_t>(owner.size())) {
    // The lock holds without its note; only the message of a second runner is poorer.
  }
}

CampaignLock::~CampaignLock() {
  if (fd_ >= 0) ::close(fd_);  // releases the lock
}

}  // namespace jam
