// A series of throws flown in the arena by the ground-station runtime (Section VII-B): the
// lockstep arena (hil/sil/arena.hpp: plant, both firmwares, radios, motion capture) and the ground
// station (groundstation/runtime) connected only by what an arena connects them with: the
// ground bus and the motion-capture frames. Two hands from outside the system complete it:
//  - the person who puts the pole on the thrower's plate while it hovers at the throw's origin
//    (at the start and whenever the pole is elsewhere, as in the paper's series; the rule is
//    `hil run`'s, hil::run::PlantExchange::hand_pole_to(), told what the runtime shows), and who
//    spoils a throw on request by pushing the thrower sideways;
//  - the referee, who judges each attempt on the plant's TRUTH: the launch (the pole's end
//    leaves plate 1), the impact on the catcher's plate, the energy right after it, and whether
//    the pole then stays within 5 degrees of upright on the catcher for 3 s (caught).
// The ground station sees neither: it gets frames and poses only.
//
// Timing per 1 ms step: the arena steps; the ground frames that arrived go to
// GroundStation::on_frame, the motion-capture frames delivered to on_mocap, then tick(); the
// frames the ground station sent go onto the ground bus (the radios carry them from the next
// step on). A series is reproducible from its seed.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "groundstation/estimation/state_estimator.hpp"
#include "groundstation/link/frame_bus.hpp"
#include "groundstation/runtime/ground_station.hpp"
#include "hil/plant/mocap.hpp"
#include "hil/sil/arena.hpp"
#include "hil/sil/ground_station_frame.hpp"
#include "hil/trials/attempt_result.hpp"

namespace hil::trials {

struct AttemptPlan {
  bool catch_it = true;                                      // false: throw only (adapt)
  Eigen::Vector2d catch_offset_m = Eigen::Vector2d::Zero();  // practice: catch this far off
  double push_sideways_m = 0.0;           // the person pushes the thrower this far in y during the throw
  pa::VehicleId thrower = pa::kVehicle1;  // the other vehicle catches
  // The ground station chooses: of `thrower` and the other, the one with the higher thrust
  // ceiling (GroundStation::stronger_thrower). Only where the person places the pole.
  bool stronger_throws = false;
  // The person puts the pole on the thrower if it is not there (a pass: it must be there already,
  // caught and balanced in the attempt before; if it is not, the attempt is not flown).
  bool place_pole = true;
  // Set: the thrower throws to this catch point (x y) instead of the Fig. 5 throw
  // (GroundStation's throw to a target); the catcher waits above it.
  std::optional<Eigen::Vector2d> target_xy_m = std::nullopt;
  // A pass: the thrower catches the throw back (AttemptRequest::thrower_catches_next).
  bool thrower_catches_next = false;
};

// The paper's series (Section VII-B): throw 1 adapts only, throws 2-7 practise with the catch
// manoeuvre 1 m off, throws 8 and 9 are caught.
std::vector<AttemptPlan> paper_series();
// One throw that adapts only, then n - 1 catches; without `trial_first`, n catches.
std::vector<AttemptPlan> catch_series(int n, bool trial_first = true);
// Passes back and forth: one throw by vehicle 1 that adapts only (as catch_series), then n
// passes: vehicle 1 throws to vehicle 2, which catches, balances and throws back from its own
// throw frame (GroundStation::throw_frame), and so on; the pole is put on vehicle 1 before the
// first pass and never again.
std::vector<AttemptPlan> pass_series(int n);
// Throws to n targets all round vehicle 1's throw origin (origin_xy_m), 2.5 to 4.5 m from it,
// every one caught by vehicle 2, which moves round the circle from target to target.
std::vector<AttemptPlan> target_series(int n, const Eigen::Vector2d& origin_xy_m);

// One row of an attempt's time series (every 10 ms); the columns of attempt_<n>.csv are in
// docs/report.md. Index 0 is vehicle 1, 1 is vehicle 2 (thrower and catcher in the paper's series).
struct TimeSample {
  double t_s;
  Vec3 vehicle1_m, vehicle2_m, pole_m, pole_axis;
  std::string task1, task2;
  std::array<Vec3, 2> plate_m;       // the plates' centres (on their surfaces)
  std::array<Vec3, 2> plate_normal;  // the plates' normals: each vehicle's body z
  std::array<Vec3, 2> pole_end_m;    // the pole's two ends
  // The inputs the ground station last commanded (RATE_THRUST as each firmware accepted it):
  // the mass-normalised collective thrust and the body rates.
  std::array<double, 2> thrust_cmd_mps2;
  std::array<Vec3, 2> rate_cmd_radps;
};

struct SeriesConfig {
  PlantConfig plant;
  sil::ArenaConfig arena;
  gs::runtime::GroundStationConfig ground_station;
  std::uint64_t seed = 1;
  double attempt_timeout_s = 40.0;  // from the request to the end of the attempt
  // The vehicles rest on the floor this long before the take-off is requested, as before a real
  // flight: the firmware learns its IMU biases at rest, which its failsafe relies on.
  double rest_before_take_off_s = 0.0;
  bool record_time_series = false;
  // Called with a line for every mission event and pole mode switch (a log for people).
  std::function<void(const std::string&)> log;
  // Measure the wall time of every GroundStation::on_mocap call (one whole ground-station frame:
  // estimator update, latency compensation, mission, controllers, catch re-planning, link).
  bool time_ground_station = false;
  // Measure the wall time of every sil::Arena::step (the plant, both firmware cores, the radios and
  // the motion capture: the arena alone, without the ground station or this runner's own work).
  bool time_arena = false;
  // Before an attempt, a person swaps the thrower's pack when the ground station finds it spent
  // (GroundStation::pack_spent): they take the pole down if the thrower holds it (a pass), the
  // thrower lands, gets a full pack and takes off again, and the pole is put on as for a first
  // throw. Off: every vehicle flies on the pack it started with.
  bool swap_spent_packs = false;
  // After the last attempt, the person takes the pole down and both vehicles land (landed()).
  bool land_after = false;
  // Called after every 1 ms step (diagnostics, tests that watch the truth). With emulated
  // firmware (arena.emulated_firmware), arena.vehicle(v).last_tick_instructions() is what that
  // step's tick cost each image.
  std::function<void(const sil::Arena&, const gs::runtime::GroundStation&)> on_step;
};

class SeriesRunner {
 public:
  explicit SeriesRunner(const SeriesConfig& config);

  // Takes off, then flies the attempts in order, calling `on_result` after each, then lands
  // (land_after). With emulated firmware, throws sil::EmulatedFirmwareError when an image stops
  // answering.
  std::vector<AttemptResult> run(const std::vector<AttemptPlan>& plans,
                                 const std::function<void(const AttemptResult&)>& on_result = {});

  // Flies on for `duration_s` without an attempt: the vehicles hold their points.
  void hover_for(double duration_s) {
    run_until([] { return false; }, duration_s);
  }

  const gs::runtime::GroundStation& ground_station() const { return gs_; }
  const sil::Arena& arena() const { return arena_; }
  // The time series of every attempt (when record_time_series), attempt by attempt.
  const std::vector<std::vector<TimeSample>>& time_series() const { return series_; }
  double simulated_time_s() const { return arena_.t_s(); }
  // The measured on_mocap durations (time_ground_station), in seconds, in call order.
  const std::vector<double>& ground_station_frame_times_s() const { return frame_times_s_; }
  // The summed wall time of the sil::Arena::step calls (time_arena), in seconds.
  double arena_time_s() const { return arena_time_s_; }
  // How many packs were swapped (swap_spent_packs).
  int packs_swapped() const { return packs_swapped_; }
  // Whether both vehicles were parked on the floor within 20 s of the landing asked for after
  // the last attempt (land_after; false without it, or when the take-off failed).
  bool landed() const { return landed_; }

 private:
  void step();
  TimeSample time_sample(double now) const;
  bool run_until(const std::function<bool()>& done, double timeout_s);
  AttemptResult fly(const AttemptPlan& plan, int number);
  // Lands `vehicle`, swaps its pack and takes it off again; false if it did not come back to hover.
  bool swap_pack(pa::VehicleId vehicle);
  void land();

  SeriesConfig config_;
  sil::Arena arena_;
  gs::link::InMemoryFrameBus bus_;
  gs::runtime::GroundStation gs_;
  std::vector<std::vector<TimeSample>> series_;
  std::vector<TimeSample>* recording_ = nullptr;
  bool crashed_ = false;
  std::uint64_t switches_logged_ = 0;
  std::vector<double> frame_times_s_;
  double arena_time_s_ = 0.0;
  std::array<pa::proto::Mode, 2> firmware_modes_{pa::proto::Mode::disarmed, pa::proto::Mode::disarmed};
  int packs_swapped_ = 0;
  bool landed_ = false;
};

}  // namespace hil::trials
