// fricrom command-line tool; see README.md and docs/ for the commands.
#include "app/commands.h"

int main(int argc, char** argv) { return fricrom::app::Run(argc, argv); }
