// A minimal consumer of the installed tricell::mpi: one rank (MPI singleton), two atoms whose
// pair goes through the periodic boundary.
#include <cstdio>

#include <tricell/mpi.hpp>

int main(int argc, char** argv) {
    MPI_Init(&argc, &argv);
    int status = 0;
    {
        const tricell::Box box = tricell::Box::from_parameters(3.0, 3.0, 3.0, 90, 90, 90);
        tricell::mpi::Decomposition decomposition(MPI_COMM_WORLD);
        tricell::mpi::LocalAtoms atoms;
        atoms.ids = {0, 1};
        atoms.positions = {0.1, 0, 0, 2.9, 0, 0};
        tricell::mpi::migrate(decomposition, box, atoms);
        tricell::NeighborOptions options;
        options.cutoff = 0.5;
        options.half = true;
        const auto pairs = tricell::mpi::compute_neighbors(decomposition, box, atoms, options);
        // A half list across ranks orients a pair with a ghost end from its owned end: here
        // 0 -> 1 through the lower face or 1 -> 0 through the upper one, one of the two.
        const bool found =
            pairs.size() == 1 &&
            ((pairs.i[0] == 0 && pairs.j[0] == 1 && pairs.shift(0) == tricell::Shift(-1, 0, 0)) ||
             (pairs.i[0] == 1 && pairs.j[0] == 0 && pairs.shift(0) == tricell::Shift(1, 0, 0)));
        if (!found) {
            std::printf("unexpected pairs (%zu)\n", pairs.size());
            status = 1;
        } else {
            std::printf("tricell mpi consumer ok\n");
        }
    }
    MPI_Finalize();
    return status;
}
