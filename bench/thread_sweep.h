// Shared by the benchmarks: their arguments (options, counts, scene names; a wrong one exits 2
// with a message), the thread counts to time Inertia at in one run, and a hash of a final
// state's bits, to show that every count computed the same bytes (DESIGN.md section 7: results
// independent of thread count).
#pragma once

#include <tbb/info.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <initializer_list>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace inertia::bench {

// Every core this process may run on: TBB's count honours the affinity mask (taskset, cgroups),
// which std::thread::hardware_concurrency() does not, and it is what a world of 0 threads uses.
inline int allCores() { return std::max(1, tbb::info::default_concurrency()); }

// Removes every "NAME VALUE" and "NAME=VALUE" from argv, so that the benchmark's own arguments
// stay where they were, and returns the last VALUE ("" for a NAME with nothing after it), or
// nothing when NAME is absent.
inline std::optional<std::string> takeOption(int& argc, char** argv, std::string_view name) {
  std::optional<std::string> value;
  for (int i = 1; i < argc; ++i) {
    const std::string_view arg = argv[i];
    int used = 0;
    if (arg == name) {
      value = i + 1 < argc ? argv[i + 1] : "";
      used = std::min(2, argc - i);
    } else if (arg.size() > name.size() && arg.starts_with(name) && arg[name.size()] == '=') {
      value = std::string(arg.substr(name.size() + 1));
      used = 1;
    } else {
      continue;
    }
    std::copy(argv + i + used, argv + argc + 1, argv + i);  // argv[argc] is null
    argc -= used;
    --i;
  }
  return value;
}

// `text` as a count in least..most; exits with a message naming `name` (the option or
// argument) when it is malformed or out of range.
inline long parseCount(std::string_view name, const std::string& text, long least, long most) {
  char* end = nullptr;
  const long n = std::strtol(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || n < least || n > most) {
    std::fprintf(stderr, "%s: expected a count in %ld..%ld, got '%s'\n", std::string(name).c_str(),
                 least, most, text.c_str());
    std::exit(2);
  }
  return n;
}

// takeOption's value as a count in 1..most (`fallback` when absent).
inline int countOption(int& argc, char** argv, std::string_view name, long most, int fallback) {
  const std::optional<std::string> value = takeOption(argc, argv, name);
  return value ? int(parseCount(name, *value, 1, most)) : fallback;
}

// The arguments left once the options are taken: names of scenes to run, each one of `known`
// (all of them when none is given). Exits with a message on any other word, so that a misspelt
// scene or an option this benchmark does not take is not silently run as "every scene".
inline std::vector<std::string> sceneNames(int argc, char** argv, std::string_view benchmark,
                                           std::initializer_list<std::string_view> known) {
  std::vector<std::string> names;
  for (int i = 1; i < argc; ++i) {
    if (std::find(known.begin(), known.end(), argv[i]) == known.end()) {
      std::string list;
      for (std::string_view k : known) list += (list.empty() ? "" : ", ") + std::string(k);
      std::fprintf(stderr, "%s: argument %d: unknown scene or option '%s' (scenes: %s)\n",
                   std::string(benchmark).c_str(), i, argv[i], list.c_str());
      std::exit(2);
    }
    names.emplace_back(argv[i]);
  }
  return names;
}

// The thread counts to time, ascending, each once, 1 always first (the speed-ups are against it).
// "--threads 1,2,16" (or "--threads=1,2,16") in argv chooses them, and is removed from argv so
// that the benchmark's own arguments stay where they were; the default is 1, 2 and all cores.
// Exits with a message on a malformed list.
inline std::vector<int> threadCounts(int& argc, char** argv) {
  const std::optional<std::string> list = takeOption(argc, argv, "--threads");
  std::vector<int> counts = {1, 2, allCores()};
  if (list) counts = {1};
  for (const char* s = list ? list->c_str() : nullptr; s; ++s) {
    char* end = nullptr;
    const long n = std::strtol(s, &end, 10);
    if (end == s || n < 1 || n > 1024 || (*end != ',' && *end != '\0')) {
      std::fprintf(stderr, "--threads: expected counts in 1..1024 separated by commas, got '%s'\n",
                   list->c_str());
      std::exit(2);
    }
    counts.push_back(int(n));
    if (*end == '\0') break;
    s = end;
  }
  std::sort(counts.begin(), counts.end());
  counts.erase(std::unique(counts.begin(), counts.end()), counts.end());
  return counts;
}

// How many times to time each of Inertia's thread counts (at least 1): "--repeat N" (or
// "--repeat=N") in argv, removed from argv like --threads. On a shared machine whose speed
// wanders from run to run, a benchmark that takes it keeps the fastest of the N runs of each count,
// taken in turn (1, 2, all, 1, 2, all, ...) so that a slow spell falls on every count alike. Exits
// with a message on a malformed count.
inline int repeatCount(int& argc, char** argv) {
  return countOption(argc, argv, "--repeat", 1000, 1);
}

// "1, 2, 16": thread counts for the reports.
inline std::string countList(const std::vector<int>& counts) {
  std::string list;
  for (int t : counts) list += (list.empty() ? "" : ", ") + std::to_string(t);
  return list;
}

// FNV-1a (64 bits) over the bytes of a state; -0 and +0, or NaNs of other payloads, hash apart, as
// they should when the question is whether two runs computed the same bits.
class BitHash {
 public:
  template <class T>
  void add(std::span<const T> values) {
    const auto* bytes = reinterpret_cast<const unsigned char*>(values.data());
    for (std::size_t i = 0; i < values.size_bytes(); ++i) {
      hash_ ^= bytes[i];
      hash_ *= 0x100000001b3ull;
    }
  }
  std::uint64_t value() const { return hash_; }

 private:
  std::uint64_t hash_ = 0xcbf29ce484222325ull;
};

}  // namespace inertia::bench
