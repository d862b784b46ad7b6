#pragma once
// A TOML table of a campaign file read key by key: each value checked for its type (and the
// simple rules every key of its type shares) as it is read, and every error a CampaignError of
// one line naming the file, the key's line and the key. What the keys mean and the rules that
// relate them are the campaign file's (campaign_file.cpp).
#include <toml++/toml.h>

#include <cstdint>
#include <map>
#include <set>
#include <string>
#include <vector>

namespace jam {

class TableReader {
 public:
  // prefix: the table's name when it is not the file's top level ("question"): keys are then
  // named "question.alpha" in messages.
  TableReader(const toml::table& table, std::string path, std::string prefix = "")
      : table_(table), path_(std::move(path)), prefix_(std::move(prefix)) {}

  /// Throws CampaignError "path:line: key: what" (no line when the key is absent).
  [[noreturn]] void fail(const std::string& key, const std::string& what) const;

  const std::string& path() const { return path_; }

  /// The node at key, marked as read; a missing required key fails.
  const toml::node* find(const std::string& key, bool required);

  double number(const std::string& key, bool required, double fallback);
  std::int64_t integer(const std::string& key, bool required, std::int64_t fallback);
  std::string string(const std::string& key, bool required, const std::string& fallback);

  /// A string value as decoded: the file is plain ASCII, but TOML escapes ("\u0000",
  /// "\u001b[31m", "\u00e9") can still put any character into it. Values name directories,
  /// checks and reports and reach terminals and file names: printable ASCII only, and at most
  /// 4096 characters (a path's limit).
  std::string printable(const std::string& key, const std::string& v) const;

  /// A string, or a number as its text ("auto"-or-number keys: tolerance, relax_energy).
  std::string text(const std::string& key, bool required, const std::string& fallback);

  bool boolean(const std::string& key, bool fallback);

  /// A required non-empty array of distinct finite numbers.
  std::vector<double> numbers(const std::string& key);

  /// A required non-empty array of distinct integers.
  std::vector<std::int64_t> integers(const std::string& key);

  /// An optional table of positive finite numbers, keys from `allowed`.
  std::map<std::string, double> number_table(const std::string& key,
                                             const std::set<std::string>& allowed,
                                             const char* what = "check");

  /// An optional array of finite numbers (repeats allowed).
  std::vector<double> optional_numbers(const std::string& key);

  /// The array of finite numbers at key (empty when absent and not required); `shape` says
  /// what it must be when it is not an array of numbers.
  std::vector<double> number_array(const std::string& key, bool required, const char* shape);

  /// An optional array of strings.
  std::vector<std::string> strings(const std::string& key);

  /// Fails on the first key of the table that was never read.
  void reject_unknown_keys() const;

 private:
  const toml::table& table_;
  std::string path_;
  std::string prefix_;
  std::set<std::string> seen_;
};

}  // namespace jam
