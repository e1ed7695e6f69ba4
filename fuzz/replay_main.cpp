// A main for the fuzz targets without libFuzzer (gcc builds: the asan preset's smoke run):
// runs LLVMFuzzerTestOneInput on every file of the given corpus folders, then on --runs N
// deterministic mutations of them (byte flips, inserts, erasures, splices): the same inputs on
// every run and machine, so a smoke failure is never a matter of luck. No coverage
// guidance: it replays the committed seeds and their neighbours under the sanitizers; the
// fuzz preset's libFuzzer build is the real fuzzer (scripts/fuzz).
#include <algorithm>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

namespace {

// The input being run, written to ./fuzz-crash-input when it aborts (a NaN check, a sanitizer
// with abort_on_error=1), so that the failure can be replayed: fuzz_TARGET fuzz-crash-input.
const std::vector<std::uint8_t>* current = nullptr;

void saveInput(int) {
  if (current) {
    if (std::FILE* f = std::fopen("fuzz-crash-input", "wb")) {
      std::fwrite(current->data(), 1, current->size(), f);
      std::fclose(f);
      std::fprintf(stderr, "input written to fuzz-crash-input\n");
    }
  }
  std::signal(SIGABRT, SIG_DFL);
  std::abort();
}

void run(const std::vector<std::uint8_t>& input) {
  current = &input;
  LLVMFuzzerTestOneInput(input.data(), input.size());
}

}  // namespace

int main(int argc, char** argv) {
  long mutations = 0;
  std::vector<std::vector<std::uint8_t>> seeds;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--runs" && i + 1 < argc) {
      mutations = std::atol(argv[++i]);
      continue;
    }
    std::vector<std::filesystem::path> files;
    if (std::filesystem::is_directory(arg)) {
      for (const auto& e : std::filesystem::directory_iterator(arg))
        if (e.is_regular_file()) files.push_back(e.path());
    } else {
      files.push_back(arg);
    }
    std::sort(files.begin(), files.end());
    for (const auto& f : files) {
      std::ifstream in(f, std::ios::binary);
      seeds.emplace_back(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    }
  }
  if (seeds.empty()) {
    std::fprintf(stderr, "usage: %s [--runs N] CORPUS_DIR_OR_FILE...\n", argv[0]);
    return 2;
  }
  std::signal(SIGABRT, saveInput);
  long runs = 0;
  for (const auto& s : seeds) run(s), ++runs;
  std::uint64_t state = 0x9E3779B97F4A7C15ull;
  const auto next = [&] {
    state ^= state << 13, state ^= state >> 7, state ^= state << 17;
    return state;
  };
  std::vector<std::uint8_t> m;
  for (long r = 0; r < mutations; ++r) {
    m = seeds[next() % seeds.size()];
    for (int k = 1 + int(next() % 4); k > 0; --k) {
      const std::size_t at = m.empty() ? 0 : next() % m.size();
      switch (next() % 4) {
        case 0:
          if (!m.empty()) m[at] = std::uint8_t(next());
          break;
        case 1:
          m.insert(m.begin() + std::ptrdiff_t(at), std::uint8_t(next()));
          break;
        case 2:
          if (!m.empty()) m.erase(m.begin() + std::ptrdiff_t(at));
          break;
        default: {
          const auto& other = seeds[next() % seeds.size()];
          if (!other.empty()) {
            const std::size_t from = next() % other.size();
            const std::size_t len = std::min<std::size_t>(other.size() - from, 1 + next() % 16);
            m.insert(m.begin() + std::ptrdiff_t(at), other.begin() + std::ptrdiff_t(from),
                     other.begin() + std::ptrdiff_t(from + len));
          }
        }
      }
    }
    run(m);
    ++runs;
  }
  std::printf("%s: %ld runs (%zu seeds)\n", argv[0], runs, seeds.size());
  return 0;
}
