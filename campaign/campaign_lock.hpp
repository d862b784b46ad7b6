#pragma once
// One owner per campaign directory: `jam campaign run` holds an advisory lock (flock) on
// <output>/.lock for as long as it runs, and a second `jam campaign run` on the same directory
// stops at once with "in use by pid P on host H" instead of racing the first for the same runs
// and temporary files. The lock dies with its process (kill -9 included), so a crashed runner
// never leaves the directory locked; the file itself stays and is reused. Under MPI, rank 0
// holds it for all ranks. On NFS, Linux carries flock over the NFS lock protocol, so it also
// holds between hosts that share the directory.
#include <string>

namespace jam {

class CampaignLock {
 public:
  /// Takes the lock of `directory` (which must exist); throws CampaignError naming the owner
  /// when another process holds it.
  explicit CampaignLock(const std::string& directory);
  CampaignLock(const CampaignLock&) = delete;
  CampaignLock& operator=(const CampaignLock&) = delete;
  ~CampaignLock();

 private:
  int fd_ = -1;
};

}  // namespace jam
