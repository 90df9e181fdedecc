// The durable adaptation store: the history of every throw and the adapted values of Section VI,
// in one SQLite database file, so that the adaptation survives restarts and crashes and a person
// can query the throws (`groundstation history`, `groundstation adaptation`).
//
// Durability. Each record() is one SQLite transaction that appends the throw and writes the
// adapted values that include it: after a crash (kill -9 in the middle of a write, a power cut)
// the file holds either both or neither, never a partial row or values out of step with the
// history. The database runs in write-ahead-log mode (readers, such as the CLI, see a consistent
// snapshot while the mission writes) with synchronous = FULL (a commit is on the disk before
// record() returns; one fsync per throw is nothing at one throw a minute). A file left by a
// crash is recovered by SQLite on the next open. tests/groundstation/adaptation_store_test.cpp
// kills a writer at random points and checks exactly this.
//
// Identity and version. The file carries SQLite's application_id (kApplicationId) and its
// user_version is the schema version (kSchemaVersion). Opening a file that is not a SQLite
// database, another application's database, a newer schema or a damaged file throws StoreError
// with a message that names the file and says which; nothing is modified.
//
// Schema 2 (schema 1 without `identifications`; a schema-1 file gains the empty table, in one
// transaction, when this program opens it, and is then schema 2: an older program refuses it as
// newer):
//   settings   (one row)  nominal catching height and waiting point, window, E*
//   adaptation (one row)  the adapted values, their sample counts, the id of the last throw they
//                         include and the first throw id since the last reset (the epoch)
//   throws     (a row per throw, id = 1, 2, ... in recording order) the ThrowRecord fields,
//                         NULL where a figure is absent, plus energy_error_J = |E - E*|
//   identifications (a row per finished motor identification, id = 1, 2, ... over all vehicles)
//                         the vehicle's node, the ground-station time, the outcome ("identified"
//                         or the refusal's name), the fit (NULL when refused) and the thrust gain
//                         at that moment (NULL when not measured); identification_record.hpp
// The adapted values are a pure function of the settings and the throws since the epoch
// (adaptation_law.hpp); check_consistency() verifies that bit for bit.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "groundstation/adaptation/adaptation_law.hpp"
#include "groundstation/adaptation/identification_record.hpp"
#include "groundstation/adaptation/throw_record.hpp"

namespace gs::adaptation {

inline constexpr std::int32_t kApplicationId = 0x50414144;  // "PAAD": pole acrobatics adaptation
inline constexpr int kSchemaVersion = 3;

// Every failure of the store: a missing, foreign, newer, corrupt or unwritable file, an invalid
// record. what() is a complete sentence naming the file.
class StoreError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct StoredThrow {
  std::int64_t id = 0;
  ThrowRecord record;
  std::optional<double> energy_error_J;  // |E - E*| (41), when the energy was recorded
};

struct AdaptationSnapshot {
  AdaptationState state;
  std::int64_t last_throw_id = 0;   // 0: no throw recorded yet
  std::int64_t epoch_first_id = 1;  // the values rest on the throws with id >= this
  std::int64_t throw_count = 0;     // rows in the history (all epochs)
};

// One vehicle's identifications: its latest, its last accepted (absent if it never had one) and
// how many there are.
struct VehicleIdentifications {
  pa::VehicleId vehicle = pa::kVehicle1;
  StoredIdentification latest;
  std::optional<StoredIdentification> last_accepted;
  std::int64_t count = 0;
};

struct ConsistencyReport {
  bool ok = false;
  std::string problem;  // empty when ok
  AdaptationState stored;
  AdaptationState recomputed;
};

class AdaptationStore {
 public:
  // Opens an existing store, or creates one with these settings if the file does not exist or is
  // an empty database (a creation that a crash interrupted leaves one). Throws StoreError.
  static AdaptationStore open_or_create(const std::string& path, const AdaptationSettings& settings);
  // Opens an existing store; a missing file is an error. Throws StoreError.
  static AdaptationStore open_existing(const std::string& path);

  AdaptationStore(AdaptationStore&&) noexcept;
  AdaptationStore& operator=(AdaptationStore&&) noexcept;
  ~AdaptationStore();

  const std::string& path() const;
  AdaptationSettings settings() const;
  AdaptationSnapshot adaptation() const;

  // Appends the throw and the adapted values that include it, atomically. Rejects a record that
  // fails validate() without writing. Returns the stored row (its id and |E - E*|).
  StoredThrow record(const ThrowRecord& record);
  // The adapted values back to the nominal ones, atomically; the history is kept and the values
  // from now on rest only on later throws.
  void reset();

  // The throws in recording order: all, or the last `last_n`.
  std::vector<StoredThrow> history(std::optional<std::int64_t> last_n = std::nullopt) const;
  std::int64_t throw_count() const;

  // Appends a finished motor identification, accepted or refused, in one transaction. Rejects a
  // record that fails validate() (identification_record.hpp) without writing. Returns the row.
  StoredIdentification record_identification(const IdentificationRecord& record);
  // The vehicle's last accepted identification: what it flies with while later fits are refused.
  std::optional<StoredIdentification> last_accepted_identification(pa::VehicleId vehicle) const;
  // The identifications in recording order: all, or the last `last_n`.
  std::vector<StoredIdentification> identifications(std::optional<std::int64_t> last_n = std::nullopt) const;
  // Per identified vehicle, in node order.
  std::vector<VehicleIdentifications> identifications_by_vehicle() const;
  std::int64_t identification_count() const;

  // SQLite's integrity check, the ids 1..n without gaps, the adaptation row pointing at the last
  // throw, the adapted values equal (exactly) to those recomputed from the history, and every
  // identification a valid one.
  ConsistencyReport check_consistency() const;

  struct Impl;  // the SQLite connection (opaque)

 private:
  explicit AdaptationStore(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace gs::adaptation
