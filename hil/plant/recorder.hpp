// `hil record`: runs a scenario and writes the motion-capture log (the input of the ground
// station's `groundstation estimate`) and, optionally, the true pole and vehicle states.
//
// Motion-capture CSV: t,body,x,y,z,qw,qx,qy,qz - one row per body per frame, body vehicle1,
// vehicle2 or pole, SI units, the quaternion rotating body vectors into the inertial frame (for
// the pole it turns body z into n), w >= 0. t is when the frame reached the ground station
// (capture time + latency), or the capture time with --stamp capture.
// Pole truth CSV: t,px,py,pz,vx,vy,vz,nx,ny,nz,wx,wy,wz,contact - the centre of mass, its
// velocity, the axis n, the angular velocity (inertial) and none/vehicle1/vehicle2/floor, at
// every plant tick.
// Vehicle truth CSV: t,vehicle,x,y,z,vx,vy,vz,qw,qx,qy,qz,wx,wy,wz,f0,f1,f2,f3 (body rates,
// motor thrusts in N).
#pragma once

#include <ostream>
#include <string>
#include <vector>

#include "hil/plant/scenario_runner.hpp"

namespace hil {

enum class MocapStamp { delivery, capture };

void write_mocap_csv(std::ostream& out, const std::vector<MocapRow>& rows,
                     MocapStamp stamp = MocapStamp::delivery);
void write_pole_truth_csv(std::ostream& out, const std::vector<PoleTruthRow>& rows);
void write_vehicle_truth_csv(std::ostream& out, const std::vector<VehicleTruthRow>& rows);
// The same file a row at a time, for a writer that streams it (`hil run --log`).
void write_vehicle_truth_header(std::ostream& out);
void write_vehicle_truth_row(std::ostream& out, const VehicleTruthRow& row);

// The whole command: args are the arguments after `record`. Prints a summary (the true launch
// and impact times among it) on `out`, messages on `err`. Returns 0 on success, 2 for bad
// arguments or a bad scenario file (with file:line), 1 if an output file cannot be written.
// Never throws.
int record_command(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);
void print_record_usage(std::ostream& out);

}  // namespace hil
