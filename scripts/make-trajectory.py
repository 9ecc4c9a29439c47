#!/usr/bin/python3
"""Writes examples/data/argon.xyz: a short Lennard-Jones argon run, 256 atoms, 10 frames.

Liquid-like argon (ASE's LJ calculator, sigma 3.405 A, epsilon 0.0104 eV, cutoff 3 sigma) in a
slightly sheared (triclinic) periodic cell, Langevin dynamics at 150 K from an expanded fcc
lattice, one frame every 25 steps of 5 fs after 200 steps of melting. Fixed seed, so the file
is the same on every run with the same ASE. Run with /usr/bin/python3 (needs ASE):

    /usr/bin/python3 scripts/make-trajectory.py [OUTPUT]
"""
import sys

import numpy as np
from ase import units
from ase.build import bulk
from ase.calculators.lj import LennardJones
from ase.io import write
from ase.md.langevin import Langevin
from ase.md.velocitydistribution import MaxwellBoltzmannDistribution

SIGMA, EPSILON = 3.405, 0.0104


def main():
    output = sys.argv[1] if len(sys.argv) > 1 else "examples/data/argon.xyz"
    rng = np.random.default_rng(20261202)
    atoms = bulk("Ar", "fcc", a=5.9, cubic=True).repeat((4, 4, 4))
    cell = np.array(atoms.cell)
    cell[2] += 0.15 * cell[0] + 0.1 * cell[1]  # a triclinic cell, same volume
    atoms.set_cell(cell, scale_atoms=True)
    atoms.calc = LennardJones(sigma=SIGMA, epsilon=EPSILON, rc=3 * SIGMA, smooth=True)
    MaxwellBoltzmannDistribution(atoms, temperature_K=300, rng=rng)
    dynamics = Langevin(atoms, 5 * units.fs, temperature_K=150, friction=0.02, rng=rng)
    dynamics.run(200)
    frames = []
    for _ in range(10):
        dynamics.run(25)
        frame = atoms.copy()
        frame.calc = None
        frames.append(frame)
    # Positions only (species and pos columns), 6 decimals: about 25 KB per frame.
    with open(output, "w") as out:
        for frame in frames:
            rows = " ".join(f"{v:.6f}" for v in np.array(frame.cell).ravel())
            out.write(f"{len(frame)}\n")
            out.write(f'Lattice="{rows}" Properties=species:S:1:pos:R:3 pbc="T T T"\n')
            for symbol, x in zip(frame.get_chemical_symbols(), frame.positions):
                out.write(f"{symbol} {x[0]:.6f} {x[1]:.6f} {x[2]:.6f}\n")


if __name__ == "__main__":
    main()
