#include "groundstation/service/socketcan_bus.hpp"

#include <stdexcept>

namespace gs::service {

SocketCanBus::SocketCanBus(const std::string& interface_name) {
  if (can_.open(interface_name.c_str()) != pa::can::SocketCan::Status::ok)
    throw std::runtime_error(can_.message());
}

}  // namespace gs::service
