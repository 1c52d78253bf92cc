// track_node: serves the track participant (the one that holds the sleepers), or any other with
// --role.
#include "server.hpp"

int main(int argc, char** argv) {
  return railcosim::node_main("track", argc, argv);
}
