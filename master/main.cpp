#include "cli/cli.hpp"

int main(int argc, char** argv) {
  return railcosim::cli::master_main(argc, argv);
}
