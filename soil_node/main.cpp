// soil_node: serves the soil participant (the soil masses under the sleepers,
// below the ballast cut), or any other with --role.
#include "server.hpp"

int main(int argc, char** argv) {
  return railcosim::node_main("soil", argc, argv);
}
