// vehicle_node: serves S1, the side of the cut that holds the wheel.
#include "server.hpp"

int main(int argc, char** argv) {
  return railcosim::node_main(railcosim::wire::ROLE_VEHICLE, argc, argv);
}
