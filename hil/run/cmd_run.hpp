// `hil run` (cmd_run.cpp), in the `hil` executable when Cyclone DDS is built (it publishes the
// motion capture on DDS).
#pragma once

namespace hil::run {

int cmd_run(int argc, char** argv);

}  // namespace hil::run
