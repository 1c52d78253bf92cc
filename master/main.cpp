#include "cli/cli.hpp"

int main(int argc, char** argv) {
  return railcosim::master_main(argc, argv);
}
