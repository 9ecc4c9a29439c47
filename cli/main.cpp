// tricell: neighbour lists, cell information and coordination numbers of crystal structure
// files (CIF, POSCAR/CONTCAR, extended XYZ). The subcommands and the exit status are in
// dispatch.cpp.
#include <string>
#include <vector>

#include "cli.hpp"

int main(int argc, char** argv) {
    const std::vector<std::string> args(argv + (argc > 0 ? 1 : 0), argv + argc);
    return tricell::cli::run(args);
}
