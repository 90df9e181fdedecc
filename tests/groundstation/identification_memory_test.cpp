// The identification each vehicle flies with (adaptation/identification_memory.hpp): an accepted
// fit replaces the kept one, a refused fit leaves it, what is kept is set on board at arming when
// it differs from the design's lag, and with a store it survives a restart.
#include "groundstation/adaptation/identification_memory.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <stdexcept>

#include "adaptation_test_support.hpp"

namespace {

using namespace gs::adaptation;
using gs::estimation::IdentificationRefusal;
using gs::estimation::IdentificationResult;
using gs::estimation::MotorIdentification;

constexpr double kDesign_s = 0.03;

IdentificationMemorySettings settings() { return {kDesign_s, 0.1}; }

AdaptationSettings adaptation_settings() { return adaptation_test::nominal_settings(); }

IdentificationResult accepted(double lag_s) {
  MotorIdentification m;
  m.time_constant_s = lag_s;
  m.time_constant_low_s = 0.97 * lag_s;
  m.time_constant_high_s = 1.03 * lag_s;
  m.inertia_gain = 1.05;
  m.round_trip_s = 0.021;
  m.rms_radps = 0.04;
  m.samples = 260;
  return {IdentificationRefusal::none, m};
}

IdentificationResult refused(IdentificationRefusal why) { return {why, std::nullopt}; }

IdentificationResult with_inertia_gain(double g) {
  IdentificationResult r = accepted(kDesign_s);
  r.identified->inertia_gain = g;
  return r;
}

}  // namespace

TEST_CASE("an accepted fit replaces the kept one, a refused fit leaves it in place") {
  IdentificationMemory memory(settings(), "", adaptation_settings());
  // Nothing kept: the firmware's design lag stays at arming.
  CHECK_FALSE(memory.kept(pa::kVehicle1));
  CHECK_FALSE(memory.lag_at_arming(pa::kVehicle1));

  // A slow motor: kept, and set on board now (the equaliser has the design's 30 ms).
  CHECK(memory.finished(pa::kVehicle1, accepted(0.045), 0.98, 10.0, kDesign_s) == 0.045);
  CHECK(memory.kept(pa::kVehicle1)->time_constant_s == 0.045);
  CHECK(memory.lag_at_arming(pa::kVehicle1) == 0.045);

  // Every refusal leaves it, sets nothing, and the next arming sets it again.
  for (const IdentificationRefusal why : gs::estimation::kAllIdentificationRefusals) {
    INFO(gs::estimation::refusal_name(why));
    CHECK_FALSE(memory.finished(pa::kVehicle1, refused(why), 0.98, 20.0, 0.045));
    CHECK(memory.kept(pa::kVehicle1)->time_constant_s == 0.045);
    CHECK(memory.lag_at_arming(pa::kVehicle1) == 0.045);
  }

  // Within the tolerance of what is set: kept, nothing sent.
  CHECK_FALSE(memory.finished(pa::kVehicle1, accepted(0.047), std::nullopt, 30.0, 0.045));
  CHECK(memory.kept(pa::kVehicle1)->time_constant_s == 0.047);
  // Back near the design's lag: set on board now (the equaliser holds 45 ms), and not at arming.
  CHECK(memory.finished(pa::kVehicle1, accepted(0.031), std::nullopt, 40.0, 0.045) == 0.031);
  CHECK_FALSE(memory.lag_at_arming(pa::kVehicle1));

  // Each vehicle its own.
  CHECK_FALSE(memory.kept(pa::kVehicle2));
  CHECK_FALSE(memory.lag_at_arming(pa::kVehicle2));
}

TEST_CASE("the tolerance: a lag within 10 % of the design's is not set at arming") {
  IdentificationMemory memory(settings(), "", adaptation_settings());
  memory.finished(pa::kVehicle1, accepted(0.0325), std::nullopt, 1.0, kDesign_s);
  CHECK_FALSE(memory.lag_at_arming(pa::kVehicle1));  // 2.5 ms off, tolerance 3.25 ms
  memory.finished(pa::kVehicle2, accepted(0.0345), std::nullopt, 1.0, kDesign_s);
  CHECK(memory.lag_at_arming(pa::kVehicle2) == 0.0345);  // 4.5 ms off, tolerance 3.45 ms
  memory.finished(pa::kVehicle2, accepted(0.025), std::nullopt, 2.0, 0.0345);
  CHECK(memory.lag_at_arming(pa::kVehicle2) == 0.025);  // a faster motor too
}

TEST_CASE("with a store, the identification survives a restart and a refused fit keeps it") {
  adaptation_test::ScratchDir dir("identification-memory");
  const std::string path = dir.file("store.sqlite");
  {
    IdentificationMemory run1(settings(), path, adaptation_settings());
    CHECK_FALSE(run1.lag_at_arming(pa::kVehicle1));
    run1.finished(pa::kVehicle1, accepted(0.052), 0.93, 12.5, kDesign_s);
    run1.finished(pa::kVehicle2, refused(IdentificationRefusal::no_telemetry), std::nullopt, 12.6, kDesign_s);
  }
  {
    // The next run sets vehicle 1's lag at its first arming, before any fit of its own.
    IdentificationMemory run2(settings(), path, adaptation_settings());
    CHECK(run2.lag_at_arming(pa::kVehicle1) == 0.052);
    CHECK(run2.kept(pa::kVehicle1)->inertia_gain == 1.05);
    CHECK_FALSE(run2.kept(pa::kVehicle2));
    // Its take-off's fit is refused: the earlier one stays, here and in the store.
    CHECK_FALSE(run2.finished(pa::kVehicle1, refused(IdentificationRefusal::saturated), 0.94, 3.0, 0.052));
    CHECK(run2.lag_at_arming(pa::kVehicle1) == 0.052);
  }
  IdentificationMemory run3(settings(), path, adaptation_settings());
  CHECK(run3.lag_at_arming(pa::kVehicle1) == 0.052);

  const AdaptationStore store = AdaptationStore::open_existing(path);
  const std::vector<StoredIdentification> rows = store.identifications();
  REQUIRE(rows.size() == 3);
  CHECK(rows[0].record.vehicle == pa::kVehicle1);
  CHECK(rows[0].record.time_s == 12.5);
  CHECK(rows[0].record.thrust_gain == 0.93);
  CHECK(outcome_name(rows[1].record.result) == "no_telemetry");
  CHECK_FALSE(rows[1].record.thrust_gain);
  CHECK(outcome_name(rows[2].record.result) == "saturated");
  CHECK(store.last_accepted_identification(pa::kVehicle1)->id == 1);
}

TEST_CASE("a fit that cannot be stored is neither kept nor set; a vehicle that is none is an error") {
  adaptation_test::ScratchDir dir("identification-memory-invalid");
  const std::string path = dir.file("store.sqlite");
  IdentificationMemory memory(settings(), path, adaptation_settings());
  memory.finished(pa::kVehicle1, accepted(0.05), std::nullopt, 1.0, kDesign_s);
  IdentificationResult bad = accepted(0.06);
  bad.identified->time_constant_s = std::nan("");
  CHECK_FALSE(memory.finished(pa::kVehicle1, bad, std::nullopt, 2.0, 0.05));
  CHECK(memory.kept(pa::kVehicle1)->time_constant_s == 0.05);
  CHECK(AdaptationStore::open_existing(path).identification_count() == 1);
  CHECK_THROWS_AS(memory.kept(pa::VehicleId(15)), std::out_of_range);
  CHECK_THROWS_AS(memory.lag_at_arming(pa::VehicleId(0)), std::out_of_range);
}

TEST_CASE("the rate loop's inertia is lowered to a lighter vehicle's, never raised, beyond the tolerance") {
  IdentificationMemory memory(settings(), "", adaptation_settings());
  CHECK_FALSE(memory.inertia_scale_to_set(pa::kVehicle1, 1.0));  // nothing kept
  memory.finished(pa::kVehicle1, with_inertia_gain(1.25), std::nullopt, 1.0, kDesign_s);
  REQUIRE(memory.inertia_scale_to_set(pa::kVehicle1, 1.0));
  CHECK(*memory.inertia_scale_to_set(pa::kVehicle1, 1.0) == Approx(0.8));
  CHECK_FALSE(memory.inertia_scale_to_set(pa::kVehicle1, 0.82));  // set already, within 10 %
  // Within the fit's accuracy of the file's: nothing to set.
  memory.finished(pa::kVehicle1, with_inertia_gain(1.05), std::nullopt, 2.0, kDesign_s);
  CHECK_FALSE(memory.inertia_scale_to_set(pa::kVehicle1, 1.0));
  CHECK(*memory.inertia_scale_to_set(pa::kVehicle1, 0.8) == Approx(1.0 / 1.05));  // back up
  // A heavier vehicle keeps the file's inertia on board.
  memory.finished(pa::kVehicle2, with_inertia_gain(0.8), std::nullopt, 3.0, kDesign_s);
  CHECK_FALSE(memory.inertia_scale_to_set(pa::kVehicle2, 1.0));
  CHECK(*memory.inertia_scale_to_set(pa::kVehicle2, 0.8) == Approx(1.0));
  // A refused fit leaves the kept one.
  memory.finished(pa::kVehicle1, refused(IdentificationRefusal::no_motion), std::nullopt, 4.0, kDesign_s);
  CHECK(*memory.inertia_scale_to_set(pa::kVehicle1, 0.8) == Approx(1.0 / 1.05));
}
