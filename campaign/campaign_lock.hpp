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

// A share of a campaign (`--shard K/N`) takes `.lock` shared, so that the N shares of a job
// array run side by side, and `.lock.shard-K-of-N` exclusive, so that each share has one
// runner; an unsharded runner excludes them all.
class CampaignLock {
 public:
  /// Takes the lock of `directory` (which must exist) for the whole campaign (shard empty) or
  /// for one share ("K-of-N"); throws CampaignError naming the owner when it is held, or with
  /// `wait` (imports, which take turns: campaign/external_import.cpp) says so on stderr and
  /// waits until it is free.
  explicit CampaignLock(const std::string& directory, const std::string& shard = "",
                        bool wait = false);
  CampaignLock(const CampaignLock&) = delete;
  CampaignLock& operator=(const CampaignLock&) = delete;
  ~CampaignLock();

 private:
  int fd_ = -1, shard_fd_ = -1;
};

}  // namespace jam
