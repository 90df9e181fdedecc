// Fuzzes the adaptation store (groundstation/adaptation/adaptation_store) opened on a corrupted
// file: the input is written as the database file, then opened, its history and adapted values
// read and its consistency checked. Every failure must be a StoreError naming the file; any
// other exception escapes and aborts, which libFuzzer reports as a crash.
//
// The file lives in /dev/shm when there is one: SQLite syncs what it writes (the store runs
// with synchronous = FULL), which on a disk would cost most of each run.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "groundstation/adaptation/adaptation_store.hpp"

namespace {

void check(bool condition) {
  if (!condition) __builtin_trap();
}

std::string scratch_path() {
  std::error_code ec;
  const std::filesystem::path dir = std::filesystem::is_directory("/dev/shm", ec)
                                        ? std::filesystem::path("/dev/shm")
                                        : std::filesystem::temp_directory_path();
  return (dir / ("pa_store_fuzz_" + std::to_string(::getpid()) + ".sqlite")).string();
}

void remove_store(const std::string& path) {
  std::error_code ec;
  for (const char* suffix : {"", "-wal", "-shm", "-journal"}) std::filesystem::remove(path + suffix, ec);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::string path = scratch_path();
  remove_store(path);
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }

  try {
    const gs::adaptation::AdaptationStore store = gs::adaptation::AdaptationStore::open_existing(path);
    const auto history = store.history();
    check(static_cast<std::int64_t>(history.size()) == store.throw_count());
    (void)store.adaptation();
    (void)store.settings();
    (void)store.history(1);
    (void)store.check_consistency();
  } catch (const gs::adaptation::StoreError& e) {
    const std::string what = e.what();
    check(what.find(std::filesystem::path(path).filename().string()) != std::string::npos);
  }
  remove_store(path);
  return 0;
}
