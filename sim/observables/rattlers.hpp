#pragma once
// Rattler removal: a particle with fewer than D+1 contacts cannot be mechanically stable,
// so it is removed together with its contacts, and removal repeats until every remaining
// particle has at least D+1 contacts (O'Hern et al.; paper's supplement, "Averaging at
// Constant Contact Number Z"). Z is then 2 N_contacts / N over the remaining particles.
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace jam {

struct RattlerAnalysis {
  std::size_t rattlers = 0;
  double contacts_per_particle = 0.0;  // over non-rattlers, 0 if all are rattlers
  std::vector<bool> is_rattler;
};

inline RattlerAnalysis find_rattlers(
    std::size_t n, const std::vector<std::pair<std::uint32_t, std::uint32_t>>& contacts,
    int min_contacts) {
  std::vector<std::uint32_t> count(n, 0), start(n + 1, 0), adj(2 * contacts.size());
  for (const auto& [i, j] : contacts) {
    ++start[i + 1];
    ++start[j + 1];
  }
  for (std::size_t i = 0; i < n; ++i) start[i + 1] += start[i];
  std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
  for (const auto& [i, j] : contacts) {
    adj[fill[i]++] = j;
    adj[fill[j]++] = i;
  }
  for (std::size_t i = 0; i < n; ++i) count[i] = start[i + 1] - start[i];

  RattlerAnalysis r;
  r.is_rattler.assign(n, false);
  std::vector<std::uint32_t> queue;
  for (std::size_t i = 0; i < n; ++i) {
    if (count[i] < static_cast<std::uint32_t>(min_contacts)) {
      r.is_rattler[i] = true;
      queue.push_back(static_cast<std::uint32_t>(i));
    }
  }
  // A contact is still present while neither end has been processed; processing a rattler
  // removes all of its remaining contacts.
  std::vector<bool> processed(n, false);
  std::size_t remaining_contacts = contacts.size();
  while (!queue.empty()) {
    const std::uint32_t i = queue.back();
    queue.pop_back();
    for (std::uint32_t k = start[i]; k < start[i + 1]; ++k) {
      const std::uint32_t j = adj[k];
      if (processed[j]) continue;
      --count[j];
      --remaining_contacts;
      if (!r.is_rattler[j] && count[j] < static_cast<std::uint32_t>(min_contacts)) {
        r.is_rattler[j] = true;
        queue.push_back(j);
      }
    }
    processed[i] = true;
  }
  for (bool b : r.is_rattler) r.rattlers += b;
  const std::size_t kept = n - r.rattlers;
  r.contacts_per_particle = kept ? 2.0 * static_cast<double>(remaining_contacts) / kept : 0.0;
  return r;
}

}  // namespace jam
