// Setpoint-stream cuts (issue 13): the closed-loop mission (take-off, hover, balance, throw,
// catch manoeuvre, after the catch) flown in the arena by the ground-station runtime, and at a
// drawn instant the radio goes silent towards both vehicles (the ground station dies). The
// vehicles' firmware is then on its own: its failsafe must level them, hover, descend and land
// with the motors off. Each cut is judged on the plant's truth, per vehicle.
//
// One mission, many cuts. The arena is copyable, so a mission is flown once per group of
// cuts_per_mission cuts and forked (copied) at each cut's step; each copy runs on without the
// ground station (nothing reaches the vehicles anyway). The mission is flown twice: first to
// learn when its phases begin and end, then to cut at instants drawn within them. Cut c (1..N)
// is drawn in phase (c - 1) mod 5 (the next phase the mission flew when it did not fly that
// one), uniformly on its millisecond grid; the phase reported is the one flown at the cut.
//
// Mission m (1..M) flies on the plant drawn with attempt_seed(seed, m), its radios losing frames
// as that plant says (trial_config.hpp), its ground station starting from what a warm-up on the
// nominal plant learnt, as in a campaign (campaign.hpp); missions run on worker processes (worker_pool.hpp), so the results
// depend on the seed (and cuts_per_mission) alone, whatever the number of workers.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "hil/plant/plant_config.hpp"
#include "hil/sil/arena.hpp"
#include "hil/trials/record_schema.hpp"

namespace hil::trials {

inline constexpr std::string_view kLostBeforeCut = "lost_before_cut";

enum class CutPhase : std::uint8_t { hover, balance, throwing, catching, after_catch };
inline constexpr int kCutPhaseCount = 5;
std::string_view cut_phase_name(CutPhase phase);

// The referee's thresholds (docs/failsafe.md).
struct CutLimits {
  double failsafe_within_s = 0.025;             // last setpoint -> firmware in failsafe_hover
  double level_tilt_rad = 5.0 * M_PI / 180.0;   // levelled: body z within this of up ...
  double level_rate_radps = 0.5;                // ... and every body rate below this (truth)
  double crash_speed_mps = 1.0;                 // touching down faster than this is a crash
  double crash_tilt_rad = 30.0 * M_PI / 180.0;  // so is touching down or resting tilted more
  double land_within_s = 40.0;                  // after the cut; not landed by then fails
};

// One vehicle's account of one cut. Times are from the last setpoint the firmware read.
struct VehicleCut {
  std::string mode_at_cut;            // the firmware's mode at the cut
  double height_m = 0.0;              // truth, centre of mass at the cut
  double tilt_at_cut_rad = 0.0;       // truth
  double failsafe_after_s = -1.0;     // to the firmware levelling on board, its hold (-1: never)
  double levelled_after_s = -1.0;     // to levelled on truth after that switch (-1: never)
  double max_tilt_rad = 0.0;          // truth, from the cut to levelled
  double touchdown_after_s = -1.0;    // to the first foot on the floor (-1: never)
  double touchdown_speed_mps = -1.0;  // truth, downwards, the step before the touchdown
  double touchdown_tilt_rad = 0.0;    // truth, at the touchdown
  double drift_m = 0.0;               // truth, horizontal, from the cut to the touchdown
  std::string final_mode;             // the firmware's mode at the end
  // On the floor (truth) with every motor command zero, whatever the firmware's mode: a touchdown
  // its impact detector classes as a crash ends in killed, motors off too (final_mode says).
  bool landed = false;
  bool motors_off = false;  // every motor command zero at the end
  bool crashed = false;     // truth: touchdown speed or tilt above the limits
  // Empty: passed; else the causes joined by '+', led by kLostBeforeCut when the mission flown
  // uncut had tilted this vehicle past 60 degrees before the cut's instant (lost by the closed
  // loop, not by the failsafe).
  std::string failure;
};

struct CutResult {
  int cut = 0;      // 1..N
  int mission = 0;  // 1..M
  std::uint64_t mission_seed = 0;
  CutPhase phase = CutPhase::hover;    // flown at the cut
  double t_cut_s = 0.0;                // mission time of the cut
  double min_separation_m = 0.0;       // truth, between the vehicles' centres after the cut
  double run_s = 0.0;                  // simulated from the cut to the end of the judgement
  std::array<VehicleCut, 2> vehicles;  // indexed by pa::act_slot()
};

struct CutsConfig {
  PlantConfig plant;  // the nominal plant; the missions' plants are drawn from its ranges
  std::uint64_t seed = 1;
  int cuts = 100;
  int jobs = 1;
  int cuts_per_mission = 50;
  CutLimits limits;
};

// Judges the cut of the mission at `at_cut`'s state: a copy of it runs with the uplink silent
// until both vehicles are landed with their motors off, or limits.land_within_s has passed.
// Fills every field but cut, mission, mission_seed and phase.
CutResult fly_cut(const sil::Arena& at_cut, const CutLimits& limits);

// Flies every cut. `progress` is called in the calling process after each mission with the
// number of cuts judged so far. Throws std::runtime_error as run_on_workers() does.
std::vector<CutResult> run_cuts(const CutsConfig& config, const std::function<void(int done)>& progress = {});

// Every field of a cut, its vehicles' too (record_schema.hpp): the workers' reports carry them all.
const Schema<CutResult>& cut_schema();

// Cuts as one line and back (the workers' reports): each cut encoded with cut_schema(), the cuts
// separated by '|'.
std::string encode_cuts(const std::vector<CutResult>& cuts);
bool decode_cuts(const std::string& line, std::vector<CutResult>& cuts);

// One row of cuts.csv: one vehicle of one cut.
struct CutRow {
  const CutResult* cut = nullptr;
  pa::VehicleId vehicle = pa::kVehicle1;
};
// The columns of cuts.csv (docs/failsafe.md): angles in degrees, the phase by name.
Schema<CutRow> cuts_csv_columns();

}  // namespace hil::trials
