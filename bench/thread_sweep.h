// Shared by the benchmarks: their arguments (options, counts, scene names; a wrong one exits 2
// with a message), the thread counts to time Inertia at in one run, and a hash of a final
// state's bits, to show that every count computed the same bytes (DESIGN.md section 7: results
// independent of thread count).
#pragma once

#include <tbb/info.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <initializer_list>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <thread>
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

// The machine's own bound on a thread count's speed-up, which no scheduler can pass: `copies`
// independent runs of the same one-thread work at once (no data shared, no synchronisation),
// against one run alone. Those runs share only the machine (its caches, memory bandwidth, a
// virtual machine's host), and `copies` threads of one world share at least as much, so
// perfect parallel code on that many threads is at most copies x alone / together times faster
// than one thread. `run()` makes and times one run and returns its ms/step; the result is the
// copies' mean. Counts above the cores are not a machine bound (the copies would take turns).
template <class Run>
double sideBySideMs(int copies, const Run& run) {
  std::vector<double> ms(std::size_t(std::max(1, copies)), 0.0);
  std::vector<std::thread> others;
  for (int i = 1; i < copies; ++i) others.emplace_back([&ms, &run, i] { ms[std::size_t(i)] = run(); });
  ms[0] = run();
  for (std::thread& t : others) t.join();
  double sum = 0;
  for (double m : ms) sum += m;
  return sum / double(ms.size());
}

// The time (ns) for two threads to hand one cache line to each other and back: a floor under
// every meeting of a step's workers (a stage's post, claims and end each move such lines
// between cores). It depends on where the system puts the two threads (one core complex, two,
// two sockets; a virtual machine's host may move them), so a benchmark prints it beside its
// speed-ups. The mean of up to `trips`, for at most a tenth of a second: on a busy machine the
// two threads may share a core, and a waiting thread yields it after a thousand spins. 0 with
// fewer than 2 cores.
inline double roundTripNs(int trips = 100000) {
  if (allCores() < 2) return 0;
  constexpr int kStop = -1;
  struct alignas(64) Line {
    std::atomic<int> value{0};
  } line;
  // Waits for `want` (or kStop: false).
  const auto wait = [&line](int want) {
    int value = 0;
    for (int spins = 0; (value = line.value.load(std::memory_order_acquire)) != want &&
                        value != kStop;)
      if (++spins > 1000) std::this_thread::yield();
    return value == want;
  };
  std::thread other([&line, &wait] {
    for (int i = 0; wait(2 * i + 1); ++i) line.value.store(2 * i + 2, std::memory_order_release);
  });
  const auto start = std::chrono::steady_clock::now();
  int done = 0;
  while (done < trips) {
    line.value.store(2 * done + 1, std::memory_order_release);
    wait(2 * done + 2);
    // The clock read every 256 trips, not to add its own cost to each.
    if (++done % 256 == 0 &&
        std::chrono::steady_clock::now() - start > std::chrono::milliseconds(100))
      break;
  }
  const auto end = std::chrono::steady_clock::now();
  line.value.store(kStop, std::memory_order_release);
  other.join();
  return std::chrono::duration<double, std::nano>(end - start).count() / done;
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
