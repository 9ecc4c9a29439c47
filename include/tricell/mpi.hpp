// tricell::mpi: neighbour search over MPI ranks by domain decomposition in fractional space.
// Umbrella header (link tricell::mpi); each piece has its own header in tricell/mpi/:
//
//   decomposition.hpp  the grid of domains (MPI_Dims_create or given), per-axis boundaries
//   atoms.hpp          the atoms a rank owns (id, caller position, payload) and migrate()
//   halo.hpp           ghosts within the cutoff of a domain, with their image shifts;
//                      forward() and reverse_sum() of per-atom values
//   neighbors.hpp      full and half lists of the owned atoms (upper halos: Newton's third
//                      law across ranks)
//   verlet.hpp         the distributed Verlet list (rebuild agreed by MPI_Allreduce)
//   balance.hpp        boundaries from the E[n], E[n^2] occupancy-moment work model
//   traffic.hpp        messages and bytes sent, counted by kind, and halo_model() (below)
//
// Weak-scaling model (one rank per domain, n atoms per rank at density rho, halo reach
// r = r_c + skin for a Verlet list, r_c for a one-off search). For a near-cubic domain of side
// l = (n / rho)^(1/3) in an orthorhombic box the fractional halo is the shell of width r, so
//     ghosts per owned atom      g = (1 + 2 r / l)^3 - 1, and g / 2 for a half list (its
//                                    halo holds the upper ghosts only, halo.hpp)
//     neighbour ranks            M = (2 ceil(r / l) + 1)^3 - 1   (once every axis has that many
//                                    domains; 26 while r < l), one message each way per exchange
//     bytes per exchange         per ghost sent: 56 at a build (id, y, c, species, radius), 40
//                                    per Verlet step (y, c), 8 w for w doubles per atom
// and none of them depends on the number of ranks P. A rank sends n (g - g_self) ghosts (half
// of it for a half list), g_self the images of its own atoms along axes with one domain (0 on a
// large grid); traffic.hpp has the model for any grid of equal domains (halo_model()), and
// DistributedVerletList::traffic() counts what each rank sent, by kind. In a triclinic box the
// fractional halo box is larger than the Cartesian shell (more ghosts, the same pairs). Exchanges
// are direct to every rank in the halo (no staged forwarding along axes), which is what keeps a
// halo several domains deep exact, at the price of M messages instead of 6. Per Verlet step that
// keeps the list: one small MPI_Allreduce (the input check with the displacement vote of the
// owned atoms), O(log P), one halo update (M messages) and, with Newton's third law, one
// reverse_sum (M messages). Per rebuild additionally: a migration among the
// halo's neighbour ranks (one MPI_Allreduce vote, then M messages) whenever every atom's new owner
// is one of them, the usual case after one Verlet interval, else the fallback of one MPI_Alltoall
// of counts (O(P) per rank, about 40 kB at P = 10^4) and an MPI_Alltoallv; a halo build (M
// messages) and the local build. So only the Allreduce latencies (log P) grow with P, and the
// Alltoall when atoms jump past the halo. Local work per rank: at a rebuild the subset search
// (NeighborOptions::query) of the n owned atoms against the n (1 + g / 2) local ones (no
// ghost-ghost pair is searched) and the list's orientation applied once to its pairs; per step
// the filter of those oriented candidates (as the serial Verlet list's refresh), the force loop
// over the half list (each pair once over all ranks) and one reverse_sum of the ghosts' forces: M
// messages, 8 w n (g - g_self) / 2 bytes for w doubles per ghost (24 per ghost sent for
// forces).
//     n = 500:    l = 8.5,  g = 3.53 (r = 2.8),  9.21 (r = 5.0)
//     n = 4000:   l = 17.1, g = 1.34 (r = 2.8),  2.98 (r = 5.0)
//     n = 32000:  l = 34.2, g = 0.58 (r = 2.8),  1.16 (r = 5.0)
//     n = 256000: l = 68.4, g = 0.27 (r = 2.8),  0.51 (r = 5.0)
// (rho = 0.8, M = 26 in every row.) Measured on this machine: examples/mpi_md/README.md.
#pragma once

#include "tricell/mpi/atoms.hpp"
#include "tricell/mpi/balance.hpp"
#include "tricell/mpi/decomposition.hpp"
#include "tricell/mpi/halo.hpp"
#include "tricell/mpi/neighbors.hpp"
#include "tricell/mpi/verlet.hpp"
