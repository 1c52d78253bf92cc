// track_node: serves S2, the side of the cut that holds the sleepers.
#include "server.hpp"

int main(int argc, char** argv) {
  return railcosim::node_main(railcosim::wire::ROLE_TRACK, argc, argv);
}
