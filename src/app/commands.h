// The fricrom command-line application: parses arguments, runs a command, writes results.
#pragma once

namespace fricrom::app {

// Entry point of the `fricrom` executable; returns the process exit status
// (0 ok, 1 numerical failure reported in the results, 2 bad input).
int Run(int argc, char** argv);

}  // namespace fricrom::app
