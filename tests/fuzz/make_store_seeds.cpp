// Writes the adaptation store fuzzer's seeds with the store itself: a new store, one with a
// few throws, and one reset after them (the throws before the epoch kept). Usage:
//   build/fuzz/tests/fuzz/make_store_seeds tests/fuzz/corpus/adaptation_store
#include <cstdio>
#include <filesystem>
#include <string>

#include "adaptation_test_support.hpp"
#include "groundstation/adaptation/adaptation_store.hpp"
#include "groundstation/model/impact.hpp"

namespace {

using gs::adaptation::AdaptationSettings;
using gs::adaptation::AdaptationStore;

AdaptationSettings seed_settings() {
  AdaptationSettings s;
  s.nominal_catch_height_m = 1.40;
  s.nominal_waiting_xy_m = {0.70, 0.05};
  s.window = 3;
  s.target_energy_J = gs::model::upright_energy_J(gs::model::PoleParams{});
  return s;
}

// Creates `dir/name` with `throws` throws, reset after the first `reset_after` (0: never).
void make_store(const std::filesystem::path& dir, const std::string& name, int throws, int reset_after) {
  const std::string path = (dir / name).string();
  std::filesystem::remove(path);
  AdaptationStore store = AdaptationStore::open_or_create(path, seed_settings());
  for (int id = 1; id <= throws; ++id) {
    store.record(adaptation_test::make_record(id));
    if (id == reset_after) store.reset();
  }
  // Closing checkpoints the write-ahead log into the file: the seed is one self-contained file.
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: make_store_seeds DIR\n");
    return 2;
  }
  const std::filesystem::path dir = argv[1];
  std::filesystem::create_directories(dir);
  make_store(dir, "new.sqlite", 0, 0);
  make_store(dir, "three_throws.sqlite", 3, 0);
  make_store(dir, "reset_after_two.sqlite", 4, 2);
  return 0;
}
