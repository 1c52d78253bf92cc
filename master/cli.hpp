// The master's command line: `master run` and (later) `master study`.
#pragma once

namespace railcosim {

// Parses the arguments and runs the command. Returns the process exit status:
// 0 when every requested run finished, 1 when a run failed, 2 for a usage or
// scene error.
int master_main(int argc, char** argv);

}  // namespace railcosim
