// fricrom command-line tool; see README.md and docs/ for the commands.
#include "app/commands.h"
#include "app/mpi_units.h"

int main(int argc, char** argv) {
  fricrom::app::MpiSession mpi(&argc, &argv);  // only under mpirun (app/mpi_units.h)
  return mpi.Finish(fricrom::app::Run(argc, argv));
}
