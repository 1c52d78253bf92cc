// vehicle_node: serves the vehicle participant (the one that holds the wheel), or any other with
// --role.
#include "server.hpp"

int main(int argc, char** argv) {
  return railcosim::node_main("vehicle", argc, argv);
}
